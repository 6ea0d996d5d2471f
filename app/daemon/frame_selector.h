// Which camera frames the daemon processes when the sensor runs faster than the SLAM should
// (slam.process_fps below camera.fps): evenly spaced on the frames' own timestamps, the rest
// released at once and counted as skipped (not dropped: the camera delivered them).
#pragma once

#include <cstdint>

namespace ale::app {

class FrameSelector {
 public:
  // process_fps 0: every frame.
  explicit FrameSelector(double process_fps = 0) { configure(process_fps); }
  void configure(double process_fps);
  // Whether the frame at t_ns is processed. Frames are due on a grid of 1 / process_fps from the
  // first one; a frame up to a quarter period early counts as on time (timestamps jitter), and a
  // stream that falls more than a period behind (a gap) restarts the grid at its next frame.
  bool take(std::int64_t t_ns);

 private:
  std::int64_t period_ns_ = 0;
  std::int64_t next_due_ns_ = 0;
  bool started_ = false;
};

}  // namespace ale::app

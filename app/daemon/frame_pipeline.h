// The per-frame work between camera and pose sink. Today: the ORB front end with the ALE
// lighting-adaptive enhancement (grading, gamma / negative path, contrast-guided CLAHE, the
// enhanced FAST ladder); the SLAM core plugs in here when it lands.
#pragma once

#include <memory>
#include <string>

#include "app/config.h"
#include "core/base/frame_log.h"
#include "core/base/image.h"
#include "core/base/memory_pool.h"
#include "core/enhance/enhancer.h"
#include "core/features/orb.h"
#include "core/frontend/frame_path.h"
#include "hal/camera.h"
#include "hal/pose_sink.h"

namespace ale::app {

struct FrameRecord {
  ale::hal::PoseEstimate pose;
  ale::hal::StatusReport status;
  ale::enhance::EnhanceReport enhance;
  FrameTimings timings;  // each stage of the frame path
};

class FramePipeline {
 public:
  Status configure(const DaemonConfig& config);
  // Buffers are sized by the first frame (warm-up); a later frame of another size is
  // kInvalidArgument.
  Status process(const ale::hal::Frame& frame, FrameRecord& record);
  // The daemon's reset-map command (the loop bumps the map id when this succeeds). Today there is
  // no map to clear; the SLAM core's reset goes here.
  Status reset_map();
  const std::vector<ale::features::Keypoint>& keypoints() const { return keypoints_; }

 private:
  ale::frontend::FramePath path_;
  std::vector<ale::features::Keypoint> keypoints_;
  std::vector<ale::features::Descriptor> descriptors_;
  int width_ = 0;
  int height_ = 0;
};

// The frame-log row of a processed frame (core/base/frame_log.h, read by ale-eval --report).
FrameLogRow frame_log_row(const FrameRecord& record);

}  // namespace ale::app

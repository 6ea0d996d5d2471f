// The per-frame work between camera and pose sink. Today: the ORB front end with the ALE
// lighting-adaptive enhancement (grading, gamma / negative path, contrast-guided CLAHE, the
// enhanced FAST ladder); the SLAM core plugs in here when it lands.
#pragma once

#include <cstdio>
#include <memory>
#include <string>

#include "app/config.h"
#include "core/base/image.h"
#include "core/base/memory_pool.h"
#include "core/enhance/enhancer.h"
#include "core/features/orb.h"
#include "hal/camera.h"
#include "hal/pose_sink.h"

namespace ale::app {

struct FrameRecord {
  ale::hal::PoseEstimate pose;
  ale::hal::StatusReport status;
  ale::enhance::EnhanceReport enhance;
};

class FramePipeline {
 public:
  Status configure(const DaemonConfig& config);
  // Buffers are sized by the first frame (warm-up); a later frame of another size is
  // kInvalidArgument.
  Status process(const ale::hal::Frame& frame, FrameRecord& record);
  const std::vector<ale::features::Keypoint>& keypoints() const { return keypoints_; }

 private:
  ale::features::OrbExtractor extractor_;
  std::vector<ale::features::Keypoint> keypoints_;
  std::vector<ale::features::Descriptor> descriptors_;
  int width_ = 0;
  int height_ = 0;
};

// One CSV line per frame, for reports (ale-eval --report) and for the robot maker's logs.
class FrameLog {
 public:
  FrameLog() = default;
  ~FrameLog();
  FrameLog(const FrameLog&) = delete;
  FrameLog& operator=(const FrameLog&) = delete;
  // kIoError naming the path when it cannot be created.
  Status open(const std::string& path);
  Status append(const FrameRecord& record);
  // Flushes and closes; kIoError if anything written was lost.
  Status close();
  bool is_open() const { return file_ != nullptr; }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
};

}  // namespace ale::app

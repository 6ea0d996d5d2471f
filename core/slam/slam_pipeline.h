// The whole per-frame path of the firmware: the front end's stages (core/frontend/frame_path.h)
// followed by the SLAM core's three, `map_ba` (the local BA and keyframe culling the last
// keyframe deferred: SlamSystem::finish_mapping), `track` (initialisation or tracking, the
// keyframe decision) and `map` (keyframe insertion, triangulation, fusion), each timed into the
// frame's record. The daemon, the replay tests and the benchmarks all run this one composition.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/base/frame_record.h"
#include "core/base/image.h"
#include "core/base/status.h"
#include "core/features/orb.h"
#include "core/frontend/frame_path.h"
#include "core/geometry/camera.h"
#include "core/slam/system.h"

namespace ale::slam {

class SlamPipeline {
 public:
  // The names of the SLAM core's stages in timings().
  static constexpr const char* kAdjustStage = "map_ba";
  static constexpr const char* kTrackStage = "track";
  static constexpr const char* kMapStage = "map";

  // camera: the real camera (with its distortion) of the frames; its image size is the only one
  // process() accepts.
  // vocabulary: place recognition's (SlamSystem::create); nullptr: none.
  static Result<std::unique_ptr<SlamPipeline>> create(const features::ExtractorConfig& features,
                                                      const SlamParams& slam, const geometry::Camera& camera,
                                                      std::shared_ptr<const place::Vocabulary> vocabulary = nullptr);

  // One frame. kFrameRejected for a frame of another size than the camera's or a timestamp
  // that does not increase; the map and the tracking state are unchanged then, so the caller can
  // count the frame and go on.
  Status process(const frontend::FrameId& id, GrayView image);

  const SlamReport& report() const { return system_->report(); }
  const features::ExtractionStats& stats() const { return path_.stats(); }
  const FrameTimings& timings() const { return path_.timings(); }
  const std::vector<features::Keypoint>& keypoints() const { return keypoints_; }
  const SlamSystem& system() const { return *system_; }
  // SlamSystem::add_odometry: one report of the MCU, before the frames it precedes.
  Status add_odometry(const OdometrySample& sample) { return system_->add_odometry(sample); }
  // SlamSystem::record_trajectory / resolve_trajectory.
  void record_trajectory(bool on) { system_->record_trajectory(on); }
  const RefinedTrajectory& resolve_trajectory() {
    system_->resolve_trajectory();
    return system_->trajectory();
  }
  // SlamSystem::save_map / load_map: the map file, between two frames.
  Result<io::MapFileSummary> save_map(const std::string& path) const { return system_->save_map(path); }
  Result<io::MapFileSummary> load_map(const std::string& path) { return system_->load_map(path); }
  // Starts a new map (the next frame initialises again) and forgets the brightness class.
  void reset();
  // The front end's enhancement parameters from the next frame on (FramePath::set_enhance); the
  // map and the tracking state are kept.
  Status set_enhance(const enhance::EnhanceParams& params) { return path_.set_enhance(params); }
  // The clock of the stage times and of SlamReport::place_ns.
  void set_clock(MonotonicClock clock) {
    path_.set_clock(clock);
    system_->set_clock(clock);
  }

 private:
  class TrackStage final : public frontend::FrameStage {
   public:
    explicit TrackStage(SlamSystem& system) : system_(system) {}
    const char* name() const override { return kTrackStage; }
    Status run(const frontend::FrameOutput& frame) override;

   private:
    SlamSystem& system_;
    std::vector<map::KeyframeFeature> features_;
  };
  // A stage that runs one step of the system that needs nothing of the frame (map_ba, map).
  class SystemStage final : public frontend::FrameStage {
   public:
    SystemStage(SlamSystem& system, const char* name, void (SlamSystem::*step)())
        : system_(system), name_(name), step_(step) {}
    const char* name() const override { return name_; }
    Status run(const frontend::FrameOutput&) override {
      (system_.*step_)();
      return {};
    }

   private:
    SlamSystem& system_;
    const char* name_;
    void (SlamSystem::*step_)();
  };

  SlamPipeline(std::unique_ptr<SlamSystem> system, int width, int height);

  std::unique_ptr<SlamSystem> system_;
  frontend::FramePath path_;
  SystemStage adjust_;
  TrackStage track_;
  SystemStage map_;
  int width_ = 0;
  int height_ = 0;
  std::vector<features::Keypoint> keypoints_;
  std::vector<features::Descriptor> descriptors_;
};

}  // namespace ale::slam

// `ale-slamd --trajectory OUT.tum`: one TUM line per frame with a pose ("t tx ty tz qx qy qz qw",
// the camera in the map frame, t in seconds), for ale-eval and evo. A new map (after tracking was
// lost for good) starts a new segment, marked by a comment line "# map <id>" that TUM readers skip;
// the frame log's map_id column says the same per frame.
#pragma once

#include <cstdint>
#include <string>

#include "app/daemon/frame_pipeline.h"
#include "core/base/text_file.h"

namespace ale::app {

class TrajectoryFile {
 public:
  // kIoError naming the path when it cannot be created.
  Status open(const std::string& path);
  // Writes the record's pose when it has one; nothing when not open.
  Status append(const FrameRecord& record);
  // kIoError if anything written was lost.
  Status close() { return file_.close(); }

 private:
  TextFileWriter file_;
  std::uint32_t map_id_ = 0;
  bool any_ = false;
};

}  // namespace ale::app

// A camera's sensor.yaml: the EuRoC / Kalibr schema that ale-slamd's camera.calibration_file and
// the replay backend read (hal/replay/dataset.h, read_euroc_sensor_yaml). Written by ale-render
// (a sequence's camera, the true lens of checkerboard views) and ale-calibrate (a fitted lens).
#pragma once

#include <string>

#include "app/tools/lib/render/camera.h"
#include "app/tools/lib/render/trajectory.h"

namespace ale::render {

// The file's text. `rate_hz` <= 0 leaves rate_hz out; `comment` is one line (the file's
// `comment:` value); `notes` are written as '#' lines above the camera's values (each line of
// it prefixed, empty for none). Numbers keep 12 significant digits.
std::string sensor_yaml_text(const PinholeCamera& camera, double rate_hz, const Rig& rig, const std::string& comment,
                             const std::string& notes = "");

// Writes text to path (replacing it); kIoError naming the path.
Status write_text_file(const std::string& path, const std::string& text);

}  // namespace ale::render

// Named sensor noise models for ale-render (`--noise-model`, docs/rendering.md): each sets the
// noise parameters of SensorParams (camera.h) to one camera's, so that results measured on
// rendered sequences can be checked not to belong to one noise model. And the JPEG-like block
// compression the `jpeg` model applies.
#pragma once

#include <string>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "app/tools/lib/render/camera.h"

namespace ale::render {

// The models' names, the default ("standard") first.
const std::vector<std::string>& noise_model_names();

// Sets the noise parameters of `sensor` (full well, sensitivity, read noise, vignetting,
// fixed-pattern and row noise, compression) to model `name`'s; exposure, gain and auto-exposure
// settings are left alone. kInvalidArgument naming the known models for another name.
Status apply_noise_model(const std::string& name, SensorParams& sensor);

// kInvalidArgument naming the first noise parameter of `sensor` outside its range (the ranges
// of ale-render's options, docs/rendering.md).
Status validate_noise(const SensorParams& sensor);

// The noise parameters in effect, one "key: value unit" per line (for sensor.yaml's notes).
std::string describe_noise(const std::string& name, const SensorParams& sensor);

// JPEG-like lossy compression of a grey image, in place: each 8x8 block (edge blocks padded by
// repeating the last row and column) is level-shifted by 128, transformed by the orthonormal 2-D
// DCT-II, each coefficient (u, v) rounded to a multiple of its step, transformed back, rounded and
// clipped to 0..255. Step(u, v) = max(1, round(s x (12 + 7 (u + v)))): 12 grey levels for the
// mean of a block up to 110 for its finest detail, with s = 50 / q below quality 50 and
// 2 - q / 50 from 50 (1 at 50, 0.5 at 75, every step 1 at 100). quality 1..100.
void compress_blocks(MutableGrayView image, int quality);

// The quantisation step of coefficient (u, v) (0..7 each) at `quality`, as compress_blocks().
int block_step(int u, int v, int quality);

}  // namespace ale::render

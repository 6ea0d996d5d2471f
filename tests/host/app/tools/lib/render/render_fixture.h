// A small, coarse-textured copy of the default room shared by the renderer tests, built once
// (it is the slow part, especially under qemu).
#pragma once

#include "app/tools/lib/render/scene.h"

namespace ale::render::test {

inline const Scene& small_scene() {
  static const Scene scene = [] {
    SceneOptions o;
    o.texel_scale = 3.0f;
    Result<Scene> s = build_default_scene(o);
    return s.ok() ? std::move(*s) : Scene{};
  }();
  return scene;
}

}  // namespace ale::render::test

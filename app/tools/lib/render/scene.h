// The room the renderer draws: an axis-aligned box (floor, four walls, ceiling) holding
// axis-aligned boxes (furniture, table legs, ceiling lamps), each face with its own albedo map.
// Rays are intersected analytically (slab tests); nothing is tessellated.
//
// World frame: x along the room's length, y across it, z up; the floor is z = 0 and the room
// spans [0, size.x] x [0, size.y] x [0, size.z] metres.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "app/tools/lib/render/texture.h"

namespace ale::render {

// Face index: 2 * axis + (1 for the face at the box's upper coordinate).
enum Face : int { kMinX = 0, kMaxX = 1, kMinY = 2, kMaxY = 3, kMinZ = 4, kMaxZ = 5 };

struct Box {
  Eigen::Vector3f lo = Eigen::Vector3f::Zero();
  Eigen::Vector3f hi = Eigen::Vector3f::Zero();
  std::array<int, 6> texture{{-1, -1, -1, -1, -1, -1}};  // index into Scene::textures, -1 = black
  // Radiance of a face that glows when the lamps are on (a lamp's diffuser), as a multiple of
  // the room's illuminance in lux; 0 for faces that only reflect.
  std::array<float, 6> emission{};
};

// A ceiling lamp: a downward-facing Lambertian emitter at `position`.
struct Lamp {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
};

// Where sunlight through a window falls on the floor: the parallelogram origin + a*edge_a +
// b*edge_b (a, b in [0, 1]) in floor (x, y) metres, with soft edges `softness_m` wide.
struct SunPatch {
  Eigen::Vector2f origin = Eigen::Vector2f::Zero();
  Eigen::Vector2f edge_a = Eigen::Vector2f::Zero();
  Eigen::Vector2f edge_b = Eigen::Vector2f::Zero();
  float softness_m = 0.03f;
};

struct Scene {
  Eigen::Vector3f size = Eigen::Vector3f(6.0f, 5.0f, 2.5f);
  std::array<int, 6> room_texture{{-1, -1, -1, -1, -1, -1}};  // walls, floor (kMinZ), ceiling (kMaxZ)
  std::vector<Box> boxes;
  std::vector<Texture> textures;
  std::vector<Lamp> lamps;
  SunPatch sun;
  // Share of the room's illuminance that arrives indirectly (from everywhere, also on the
  // ceiling); the rest comes from the lamps.
  float ambient_fraction = 0.4f;
  // Direct lamp light averaged over the floor, so that a room at E lux has about E lux on its
  // floor (set by finish_lighting()).
  float lamp_normaliser = 1.0f;

  int add_texture(Texture t);
  // Computes lamp_normaliser from the lamps and the floor.
  void finish_lighting();
  // Lamp light (before scaling by the room's illuminance) at p on a surface with normal n.
  float lamp_factor(const Eigen::Vector3f& p, const Eigen::Vector3f& n) const;
  // Sunlight weight in [0, 1] at floor point (x, y).
  float sun_weight(float x, float y) const;
  // True when p is inside a box or closer than margin_m to it (a camera there sees nothing real).
  bool inside_box(const Eigen::Vector3f& p, float margin_m) const;
};

// A ray's first hit. box == -1 means the room's own faces.
struct Hit {
  float t = 0.0f;  // distance along the (unit) direction
  int box = -1;
  int face = 0;
};

// First surface hit by the ray origin + t * dir (dir unit length, origin inside the room).
// Always hits something when the origin is inside the room.
bool cast_ray(const Scene& scene, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, Hit& hit);

// Surface coordinates (u, v) in metres of point p on face `face` of the box [lo, hi]. Vertical
// faces: v is the height above lo.z and u grows to the right of a viewer looking at the face
// (from outside a box, or from inside the room when `inward`). Horizontal faces: u = x, v = y.
Eigen::Vector2f face_uv(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int face, bool inward,
                        const Eigen::Vector3f& p);
// Width and height of a face in the (u, v) coordinates above.
Eigen::Vector2f face_size(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int face);

struct SceneOptions {
  std::uint32_t seed = 0x5CE4E;   // procedural textures; the room's layout does not change
  float texel_scale = 1.0f;       // >1 makes coarser (faster to build) textures, for tests
  // Photographs (grey) to use instead of the procedural materials, one per surface in turn.
  std::vector<GrayImage> photos;
  float photo_width_m = 1.2f;     // a photo covers this width of a surface and repeats
};

// The default living room: plank floor with a patterned rug, plaster walls with skirting boards,
// sockets, posters and a door, a sofa, a bookshelf, a cabinet, a table with legs, a toy box and
// two ceiling lamps; a sun patch on the floor near the start of the default loop.
Result<Scene> build_default_scene(const SceneOptions& options);

// Two living rooms side by side (12 x 5 x 2.5 m): the second a copy of the first moved 6 m along
// x, with the same textures (the floor, ceiling and long walls repeat every 6 m), a partition
// 10 cm thick at x = 6 m showing the living room's east wall to the left and its west wall to the
// right, with a floor-to-ceiling opening 0.9 m wide where the east wall's door is (y 3.0-3.9 m).
// A place in one room looks like the same place in the other: the scene for false
// relocalisation.
Result<Scene> build_twin_scene(const SceneOptions& options);

// A hall of `size` (x, y, z in metres, 1.5 .. 200) for a recorded flight: walls with posters in
// rows, doors and sockets, a plank floor with rugs, lamps on a grid (at most 3 x 3); a bookshelf
// and a cabinet against each wall and up to 8 free-standing crates and pillars, each only where
// every point of `keep_clear` (the flight's body and camera positions) is at least `clearance_m`
// away from it. The layout comes from options.seed like the textures.
Result<Scene> build_hall_scene(const SceneOptions& options, const Eigen::Vector3f& size,
                               const std::vector<Eigen::Vector3f>& keep_clear, float clearance_m);

// Adds a small glowing cube (side `size_m`, emission as in Box) centred at `centre`: a marker
// whose image position tests the projection.
void add_marker(Scene& scene, const Eigen::Vector3f& centre, float size_m, float emission);

}  // namespace ale::render

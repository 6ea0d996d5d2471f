#include "app/tools/lib/render/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "app/tools/lib/render/materials.h"
#include "app/tools/lib/render/rng.h"

namespace ale::render {

int Scene::add_texture(Texture t) {
  textures.push_back(std::move(t));
  return static_cast<int>(textures.size()) - 1;
}

float Scene::lamp_factor(const Eigen::Vector3f& p, const Eigen::Vector3f& n) const {
  float sum = 0.0f;
  for (const Lamp& lamp : lamps) {
    const Eigen::Vector3f d = lamp.position - p;
    const float d2 = d.squaredNorm();
    if (d2 < 1e-6f) continue;
    const float inv = 1.0f / std::sqrt(d2);
    const float cos_surface = n.dot(d) * inv;
    const float cos_lamp = d.z() * inv;  // the lamp shines downwards
    if (cos_surface <= 0.0f || cos_lamp <= 0.0f) continue;
    sum += cos_surface * cos_lamp / d2;
  }
  return sum;
}

void Scene::finish_lighting() {
  // Mean lamp light on a 5 cm grid over the floor.
  double total = 0.0;
  int count = 0;
  const Eigen::Vector3f up(0.0f, 0.0f, 1.0f);
  for (float y = 0.025f; y < size.y(); y += 0.05f)
    for (float x = 0.025f; x < size.x(); x += 0.05f) {
      total += lamp_factor(Eigen::Vector3f(x, y, 0.0f), up);
      ++count;
    }
  lamp_normaliser = (count > 0 && total > 0.0) ? static_cast<float>(count / total) : 1.0f;
}

float Scene::sun_weight(float x, float y) const {
  // Coordinates (a, b) of the point in the parallelogram's edges, then a soft box in them.
  const float det = sun.edge_a.x() * sun.edge_b.y() - sun.edge_a.y() * sun.edge_b.x();
  if (std::fabs(det) < 1e-9f) return 0.0f;
  const float px = x - sun.origin.x();
  const float py = y - sun.origin.y();
  const float a = (px * sun.edge_b.y() - py * sun.edge_b.x()) / det;
  const float b = (sun.edge_a.x() * py - sun.edge_a.y() * px) / det;
  const float soft_a = sun.softness_m / std::max(1e-6f, sun.edge_a.norm());
  const float soft_b = sun.softness_m / std::max(1e-6f, sun.edge_b.norm());
  auto ramp = [](float v, float soft) {
    const float in = std::min(v, 1.0f - v) / soft + 0.5f;
    return std::clamp(in, 0.0f, 1.0f);
  };
  return ramp(a, soft_a) * ramp(b, soft_b);
}

bool Scene::inside_box(const Eigen::Vector3f& p, float margin_m) const {
  for (const Box& b : boxes) {
    if ((p.array() > b.lo.array() - margin_m).all() && (p.array() < b.hi.array() + margin_m).all()) return true;
  }
  return false;
}

bool cast_ray(const Scene& scene, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, Hit& hit) {
  Eigen::Vector3f inv;
  for (int a = 0; a < 3; ++a) {
    const float d = std::fabs(dir[a]) < 1e-9f ? 1e-9f : dir[a];
    inv[a] = 1.0f / d;
  }
  // The room, seen from inside: the nearest exit face.
  float best = std::numeric_limits<float>::infinity();
  int best_face = 0;
  for (int a = 0; a < 3; ++a) {
    const bool up = inv[a] > 0.0f;
    const float t = ((up ? scene.size[a] : 0.0f) - origin[a]) * inv[a];
    if (t < best) {
      best = t;
      best_face = 2 * a + (up ? 1 : 0);
    }
  }
  int best_box = -1;
  const int n = static_cast<int>(scene.boxes.size());
  for (int i = 0; i < n; ++i) {
    const Box& b = scene.boxes[static_cast<std::size_t>(i)];
    float t_near = -std::numeric_limits<float>::infinity();
    float t_far = std::numeric_limits<float>::infinity();
    int near_axis = 0;
    for (int a = 0; a < 3; ++a) {
      float t0 = (b.lo[a] - origin[a]) * inv[a];
      float t1 = (b.hi[a] - origin[a]) * inv[a];
      if (t0 > t1) std::swap(t0, t1);
      if (t0 > t_near) {
        t_near = t0;
        near_axis = a;
      }
      t_far = std::min(t_far, t1);
    }
    // Only entries in front of the origin count: from inside a box, it is invisible.
    if (t_near <= t_far && t_near > 1e-5f && t_near < best) {
      best = t_near;
      best_box = i;
      best_face = 2 * near_axis + (inv[near_axis] > 0.0f ? 0 : 1);
    }
  }
  hit.t = best;
  hit.box = best_box;
  hit.face = best_face;
  return std::isfinite(best);
}

Eigen::Vector2f face_uv(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int face, bool inward,
                        const Eigen::Vector3f& p) {
  const int axis = face / 2;
  const bool at_max = (face & 1) != 0;
  // Normal towards the viewer: outward for a box, inward for the room.
  const bool normal_positive = at_max != inward;
  switch (axis) {
    case 0:
      return {normal_positive ? p.y() - lo.y() : hi.y() - p.y(), p.z() - lo.z()};
    case 1:
      return {normal_positive ? hi.x() - p.x() : p.x() - lo.x(), p.z() - lo.z()};
    default:
      return {p.x() - lo.x(), p.y() - lo.y()};
  }
}

Eigen::Vector2f face_size(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int face) {
  const Eigen::Vector3f s = hi - lo;
  switch (face / 2) {
    case 0:
      return {s.y(), s.z()};
    case 1:
      return {s.x(), s.z()};
    default:
      return {s.x(), s.y()};
  }
}

void add_marker(Scene& scene, const Eigen::Vector3f& centre, float size_m, float emission) {
  Box b;
  b.lo = centre - Eigen::Vector3f::Constant(0.5f * size_m);
  b.hi = centre + Eigen::Vector3f::Constant(0.5f * size_m);
  const int white = scene.add_texture(Texture(GrayImage(1, 1, 255), 1.0f, true));
  b.texture.fill(white);
  b.emission.fill(emission);
  scene.boxes.push_back(b);
}

namespace {

// Builds textures either procedurally or from the photographs, one face at a time.
class SceneBuilder {
 public:
  explicit SceneBuilder(const SceneOptions& o) : opt_(o) {}

  // A face texture: `paint` fills a canvas of the face's size at `texel_m` (scaled by the
  // options), unless photographs replace the procedural materials.
  template <class Paint>
  int face(Scene& scene, Eigen::Vector2f size_m, float texel_m, Paint paint) {
    if (!opt_.photos.empty()) return photo(scene);
    const float texel = texel_m * opt_.texel_scale;
    GrayImage img = make_canvas(size_m.x(), size_m.y(), texel, 0.5f);
    paint(img, texel, next_seed());
    return scene.add_texture(Texture(std::move(img), texel, false));
  }

 private:
  std::uint32_t next_seed() { return opt_.seed * 2654435761u + 97u * ++counter_; }

  int photo(Scene& scene) {
    const GrayImage& src = opt_.photos[photo_index_++ % opt_.photos.size()];
    // Flipped so that the photo's top row lands at the top of vertical surfaces (v grows up).
    GrayImage img(src.width, src.height);
    for (int y = 0; y < src.height; ++y)
      std::copy_n(src.pixels.begin() + static_cast<std::ptrdiff_t>(src.height - 1 - y) * src.width, src.width,
                  img.pixels.begin() + static_cast<std::ptrdiff_t>(y) * src.width);
    return scene.add_texture(Texture(std::move(img), opt_.photo_width_m / static_cast<float>(src.width), true));
  }

  const SceneOptions& opt_;
  std::uint32_t counter_ = 0;
  std::size_t photo_index_ = 0;
};

constexpr float kFloorTexel = 0.0025f;
constexpr float kWallTexel = 0.003f;
constexpr float kCeilingTexel = 0.008f;
constexpr float kFurnitureTexel = 0.0025f;

struct WallDecor {
  std::vector<RectM> posters;
  std::vector<float> sockets_u;
  std::vector<RectM> doors;
};

void paint_wall(GrayImage& img, float texel, std::uint32_t seed, const WallDecor& decor) {
  paint_plaster(img, texel, 0.66f, 0.08f, seed);
  const float width = static_cast<float>(img.width) * texel;
  paint_rect(img, texel, {0.0f, 0.0f, width, 0.08f}, 0.86f);       // skirting board
  paint_rect(img, texel, {0.0f, 0.08f, width, 0.006f}, 0.5f);      // its top edge
  paint_rect(img, texel, {0.0f, 0.0f, width, 0.004f}, 0.25f);      // the gap to the floor
  std::uint32_t s = seed;
  for (const RectM& d : decor.doors) paint_panel(img, texel, d, 0.42f, 0.07f, ++s);
  for (const RectM& p : decor.posters) paint_poster(img, texel, p, ++s * 31u);
  for (float u : decor.sockets_u) paint_socket(img, texel, u, 0.30f);
}

// Walls (decor in the order kMinX, kMaxX, kMinY, kMaxY), ceiling, and the floor `paint_floor`
// draws.
template <class PaintFloor>
void add_room_faces(Scene& scene, SceneBuilder& b, const WallDecor* const decor[4], PaintFloor paint_floor) {
  const Eigen::Vector3f zero = Eigen::Vector3f::Zero();
  for (int f = 0; f < 4; ++f) {
    const WallDecor& d = *decor[f];
    scene.room_texture[static_cast<std::size_t>(f)] =
        b.face(scene, face_size(zero, scene.size, f), kWallTexel,
               [&](GrayImage& img, float texel, std::uint32_t seed) { paint_wall(img, texel, seed, d); });
  }
  scene.room_texture[kMinZ] = b.face(scene, face_size(zero, scene.size, kMinZ), kFloorTexel, paint_floor);
  scene.room_texture[kMaxZ] = b.face(scene, face_size(zero, scene.size, kMaxZ), kCeilingTexel,
                                     [](GrayImage& img, float texel, std::uint32_t seed) {
                                       paint_plaster(img, texel, 0.82f, 0.04f, seed);
                                     });
}

// A piece of furniture; faces marked hidden (against a wall or the floor) stay untextured.
template <class PaintFace>
std::size_t add_box(Scene& scene, SceneBuilder& b, Eigen::Vector3f lo, Eigen::Vector3f hi, PaintFace paint_face,
                    std::array<bool, 6> hidden) {
  Box box;
  box.lo = lo;
  box.hi = hi;
  for (int f = 0; f < 6; ++f) {
    if (hidden[static_cast<std::size_t>(f)]) continue;
    box.texture[static_cast<std::size_t>(f)] =
        b.face(scene, face_size(lo, hi, f), kFurnitureTexel,
               [&](GrayImage& img, float texel, std::uint32_t seed) { paint_face(f, img, texel, seed); });
  }
  scene.boxes.push_back(box);
  return scene.boxes.size() - 1;
}

// A ceiling lamp centred at (x, y): a 0.5 m square diffuser 6 cm below the ceiling.
void add_lamp(Scene& scene, SceneBuilder& b, float x, float y) {
  const float top = scene.size.z();
  const std::size_t i = add_box(scene, b, {x - 0.25f, y - 0.25f, top - 0.06f}, {x + 0.25f, y + 0.25f, top},
                                [](int, GrayImage& img, float texel, std::uint32_t seed) {
                                  paint_plaster(img, texel, 0.9f, 0.02f, seed);
                                },
                                {false, false, false, false, false, true});
  scene.boxes[i].emission[kMinZ] = 30.0f;
  Lamp lamp;
  lamp.position = Eigen::Vector3f(x, y, top - 0.07f);
  scene.lamps.push_back(lamp);
}

void paint_fabric_face(int, GrayImage& img, float texel, std::uint32_t seed) { paint_fabric(img, texel, 0.24f, seed); }

void paint_bookshelf_face(int f, GrayImage& img, float texel, std::uint32_t seed, int front) {
  if (f == front)
    paint_books(img, texel, 0.38f, seed);
  else
    paint_wood(img, texel, 0.45f, seed);
}

void paint_printed_face(int, GrayImage& img, float texel, std::uint32_t seed) {
  paint_poster(img, texel, {0.0f, 0.0f, static_cast<float>(img.width) * texel, static_cast<float>(img.height) * texel},
               seed);
}

Status check_options(const SceneOptions& options) {
  if (!(options.texel_scale >= 0.25f && options.texel_scale <= 64.0f))
    return invalid_argument("scene: texel_scale " + std::to_string(options.texel_scale) + " outside [0.25, 64]");
  if (!(options.photo_width_m > 0.01f))
    return invalid_argument("scene: photo_width_m must be > 0.01 m");
  for (std::size_t i = 0; i < options.photos.size(); ++i)
    if (options.photos[i].width < 2 || options.photos[i].height < 2)
      return invalid_argument("scene: photo " + std::to_string(i) + " is smaller than 2x2");
  return {};
}

// Posters in rows up the wall, doors along the bottom every 6-10 m, sockets every 2.5-4 m.
WallDecor hall_wall_decor(float width, float height, SplitMix64& g) {
  auto uni = [&g](float lo, float hi) { return lo + (hi - lo) * g.uniform(); };
  WallDecor d;
  for (float u = uni(1.5f, 4.0f); u + 1.0f < width; u += uni(6.0f, 10.0f)) d.doors.push_back({u, 0.0f, 0.9f, 2.05f});
  for (float row = 0.15f; row + 0.9f < height - 0.3f; row += 1.6f) {
    for (float u = uni(0.2f, 0.8f); u + 0.5f < width;) {
      const float w = uni(0.5f, 1.3f);
      const RectM poster{u, row + uni(0.0f, 0.5f), std::min(w, width - u), uni(0.4f, 1.1f)};
      const bool on_door = std::any_of(d.doors.begin(), d.doors.end(), [&](const RectM& door) {
        return poster.v0 < door.v0 + door.height && poster.u0 < door.u0 + door.width && door.u0 < poster.u0 + poster.width;
      });
      if (!on_door) d.posters.push_back(poster);
      u += w + uni(0.3f, 1.2f);
    }
  }
  for (float u = uni(0.5f, 2.0f); u < width - 0.2f; u += uni(2.5f, 4.0f)) d.sockets_u.push_back(u);
  return d;
}

// Distance from p to the box [lo, hi] (0 inside).
float distance_to_box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const Eigen::Vector3f& p) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0f).norm();
}

}  // namespace

Result<Scene> build_default_scene(const SceneOptions& options) {
  ALE_RETURN_IF_ERROR(check_options(options));
  Scene scene;
  SceneBuilder b(options);

  // Walls: u runs left to right as seen from inside the room, v is the height.
  WallDecor south;  // y = 0, seen looking -y; u = 6 - x
  south.posters = {{0.5f, 0.25f, 0.7f, 0.5f}, {2.6f, 0.9f, 0.9f, 0.7f}, {4.3f, 0.15f, 0.5f, 0.65f}};
  south.sockets_u = {1.6f, 3.9f};
  WallDecor north;  // y = 5, seen looking +y; u = x
  north.posters = {{1.3f, 1.1f, 1.2f, 0.8f}, {3.5f, 0.2f, 0.6f, 0.45f}, {4.6f, 0.7f, 0.8f, 1.0f}};
  north.sockets_u = {3.3f, 5.5f};
  WallDecor west;  // x = 0, seen looking -x; u = y
  west.posters = {{0.2f, 0.2f, 0.6f, 0.4f}, {2.6f, 0.15f, 0.8f, 0.6f}, {3.7f, 0.9f, 0.9f, 0.7f}};
  west.sockets_u = {2.45f, 4.5f};
  WallDecor east;  // x = 6, seen looking +x; u = 5 - y
  east.doors = {{1.1f, 0.0f, 0.9f, 2.05f}};
  east.posters = {{2.3f, 0.3f, 0.6f, 0.5f}, {0.2f, 1.0f, 0.6f, 0.8f}};
  east.sockets_u = {2.15f, 4.6f};
  const WallDecor* const decor[4] = {&west, &east, &south, &north};
  add_room_faces(scene, b, decor, [](GrayImage& img, float texel, std::uint32_t seed) {
    paint_planks(img, texel, seed);
    paint_rug(img, texel, {2.2f, 1.9f, 1.8f, 1.2f}, seed + 1u);
  });

  // Furniture. Faces against a wall or the floor are never seen and stay untextured.
  auto add_box = [&](Eigen::Vector3f lo, Eigen::Vector3f hi, auto paint_face, std::array<bool, 6> hidden) {
    return render::add_box(scene, b, lo, hi, paint_face, hidden);
  };
  auto fabric = paint_fabric_face;
  auto wood = [](float albedo) {
    return [albedo](int, GrayImage& img, float texel, std::uint32_t seed) { paint_wood(img, texel, albedo, seed); };
  };
  // Sofa against the north wall: seat, back, two arms.
  add_box({1.0f, 4.1f, 0.0f}, {3.0f, 5.0f, 0.42f}, fabric, {false, false, false, true, true, false});
  add_box({1.0f, 4.78f, 0.42f}, {3.0f, 5.0f, 0.85f}, fabric, {false, false, false, true, true, false});
  add_box({1.0f, 4.1f, 0.42f}, {1.18f, 4.78f, 0.62f}, fabric, {false, false, false, true, true, false});
  add_box({2.82f, 4.1f, 0.42f}, {3.0f, 4.78f, 0.62f}, fabric, {false, false, false, true, true, false});
  // Bookshelf against the west wall, books facing +x.
  add_box({0.0f, 1.0f, 0.0f}, {0.35f, 2.2f, 1.9f},
          [](int f, GrayImage& img, float texel, std::uint32_t seed) { paint_bookshelf_face(f, img, texel, seed, kMaxX); },
          {true, false, false, false, true, false});
  // Cabinet against the east wall with two doors facing -x.
  add_box({5.5f, 0.5f, 0.0f}, {6.0f, 1.7f, 0.9f},
          [](int f, GrayImage& img, float texel, std::uint32_t seed) {
            paint_wood(img, texel, 0.55f, seed);
            if (f == kMinX) {
              paint_panel(img, texel, {0.02f, 0.06f, 0.57f, 0.8f}, 0.6f, 0.05f, seed + 1u);
              paint_panel(img, texel, {0.61f, 0.06f, 0.57f, 0.8f}, 0.6f, 0.05f, seed + 2u);
              paint_rect(img, texel, {0.0f, 0.0f, 1.2f, 0.06f}, 0.1f);  // plinth shadow
            }
          },
          {false, true, false, false, true, false});
  // Table: top and four legs; the robot sees the underside of the top.
  add_box({0.8f, 0.4f, 0.70f}, {2.0f, 1.2f, 0.74f}, wood(0.5f), {false, false, false, false, false, false});
  for (float lx : {0.84f, 1.91f})
    for (float ly : {0.44f, 1.11f})
      add_box({lx, ly, 0.0f}, {lx + 0.05f, ly + 0.05f, 0.70f}, wood(0.3f), {false, false, false, false, true, true});
  // A printed toy box.
  add_box({3.6f, 0.2f, 0.0f}, {4.0f, 0.6f, 0.35f},
          paint_printed_face,
          {false, false, false, false, true, false});
  // Ceiling lamps with glowing diffusers.
  for (float lx : {2.0f, 4.0f}) add_lamp(scene, b, lx, 2.5f);
  // Afternoon sun through a window in the north wall, slanted across the floor.
  scene.sun.origin = Eigen::Vector2f(3.7f, 2.9f);
  scene.sun.edge_a = Eigen::Vector2f(1.2f, 0.0f);
  scene.sun.edge_b = Eigen::Vector2f(0.4f, 0.9f);
  scene.finish_lighting();
  return scene;
}

namespace {

// Columns [first, first + count) of a texture's full-resolution map, as a new texture.
Texture columns_of(const Texture& src, long first, long count, bool repeat) {
  const GrayImage& full = src.level(0);
  first = std::clamp<long>(first, 0, full.width - 1);
  count = std::clamp<long>(count, 1, full.width - first);
  GrayImage img(static_cast<int>(count), full.height);
  for (int y = 0; y < full.height; ++y)
    std::copy_n(full.pixels.begin() + static_cast<std::ptrdiff_t>(y) * full.width + first, count,
                img.pixels.begin() + static_cast<std::ptrdiff_t>(y) * count);
  return Texture(std::move(img), src.texel_m(), repeat);
}

// A copy of texture `index` starting `offset_m` along u: a face that starts there continues it.
int add_shifted(Scene& scene, int index, float offset_m) {
  const Texture& src = scene.textures[static_cast<std::size_t>(index)];
  Texture t = columns_of(src, std::lround(offset_m / src.texel_m()), src.level(0).width, false);
  return scene.add_texture(std::move(t));
}
// A copy of texture `index` cut to `period_m` along u and repeating.
int add_periodic(Scene& scene, int index, float period_m) {
  const Texture& src = scene.textures[static_cast<std::size_t>(index)];
  Texture t = columns_of(src, 0, std::lround(period_m / src.texel_m()), true);
  return scene.add_texture(std::move(t));
}

}  // namespace

Result<Scene> build_twin_scene(const SceneOptions& options) {
  Result<Scene> one = build_default_scene(options);
  if (!one.ok()) return one.status();
  Scene scene = std::move(*one);
  const Eigen::Vector3f room = scene.size;
  const Eigen::Vector3f shift(room.x(), 0.0f, 0.0f);
  scene.size.x() = 2.0f * room.x();
  // Faces along the length tile with the room's length, so that both halves look alike.
  for (int f : {kMinY, kMaxY, kMinZ, kMaxZ}) {
    int& t = scene.room_texture[static_cast<std::size_t>(f)];
    if (t >= 0) t = add_periodic(scene, t, room.x());
  }
  const std::size_t furniture = scene.boxes.size();
  for (std::size_t i = 0; i < furniture; ++i) {
    Box b = scene.boxes[i];
    b.lo += shift;
    b.hi += shift;
    scene.boxes.push_back(b);
  }
  const std::size_t lamps = scene.lamps.size();
  for (std::size_t i = 0; i < lamps; ++i) {
    Lamp l = scene.lamps[i];
    l.position += shift;
    scene.lamps.push_back(l);
  }
  // The partition: the east wall's face towards the left room, the west wall's towards the right,
  // each continuing where its part of the wall starts; an opening from y0 to y1.
  const int east = scene.room_texture[kMaxX];
  const int west = scene.room_texture[kMinX];
  constexpr float kHalfThick = 0.05f;
  constexpr float kOpening0 = 3.0f;
  constexpr float kOpening1 = 3.9f;
  const float x = room.x();
  Box low;  // y from 0 to the opening; its kMinX face has u = y0 - y, the wall's u = depth - y
  low.lo = Eigen::Vector3f(x - kHalfThick, 0.0f, 0.0f);
  low.hi = Eigen::Vector3f(x + kHalfThick, kOpening0, room.z());
  Box high;  // from the opening to the far wall; its kMaxX face has u = y - y1, the wall's u = y
  high.lo = Eigen::Vector3f(x - kHalfThick, kOpening1, 0.0f);
  high.hi = Eigen::Vector3f(x + kHalfThick, room.y(), room.z());
  if (east >= 0) {
    low.texture[kMinX] = add_shifted(scene, east, room.y() - kOpening0);
    high.texture[kMinX] = east;
  }
  if (west >= 0) {
    low.texture[kMaxX] = west;
    high.texture[kMaxX] = add_shifted(scene, west, kOpening1);
    low.texture[kMaxY] = west;  // the opening's sides
    high.texture[kMinY] = west;
  }
  scene.boxes.push_back(low);
  scene.boxes.push_back(high);
  scene.finish_lighting();
  return scene;
}

Result<Scene> build_hall_scene(const SceneOptions& options, const Eigen::Vector3f& size,
                               const std::vector<Eigen::Vector3f>& keep_clear, float clearance_m) {
  ALE_RETURN_IF_ERROR(check_options(options));
  if (!(size.minCoeff() >= 1.5f && size.maxCoeff() <= 200.0f))
    return invalid_argument("scene: hall size outside 1.5 .. 200 m");
  if (!(clearance_m >= 0.0f)) return invalid_argument("scene: clearance must be >= 0");
  Scene scene;
  scene.size = size;
  SceneBuilder b(options);
  SplitMix64 g(0x4A11ULL ^ (static_cast<std::uint64_t>(options.seed) << 20));
  auto uni = [&g](float lo, float hi) { return lo + (hi - lo) * g.uniform(); };

  WallDecor walls[4];
  for (int f = 0; f < 4; ++f) {
    const Eigen::Vector2f face = face_size(Eigen::Vector3f::Zero(), size, f);
    walls[f] = hall_wall_decor(face.x(), face.y(), g);
  }
  const WallDecor* const decor[4] = {&walls[0], &walls[1], &walls[2], &walls[3]};
  std::vector<RectM> rugs;
  const int n_rugs = std::max(1, static_cast<int>(size.x() * size.y() / 20.0f));
  for (int i = 0; i < n_rugs; ++i) {
    const float w = uni(1.2f, 2.6f);
    const float h = uni(0.9f, 1.8f);
    rugs.push_back({uni(0.2f, std::max(0.2f, size.x() - w - 0.2f)), uni(0.2f, std::max(0.2f, size.y() - h - 0.2f)), w, h});
  }
  add_room_faces(scene, b, decor, [&rugs](GrayImage& img, float texel, std::uint32_t seed) {
    paint_planks(img, texel, seed);
    for (const RectM& r : rugs) paint_rug(img, texel, r, ++seed);
  });

  auto clear = [&](const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
    for (const Box& other : scene.boxes)
      if ((lo.array() < other.hi.array() + 0.1f).all() && (other.lo.array() - 0.1f < hi.array()).all()) return false;
    return std::none_of(keep_clear.begin(), keep_clear.end(),
                        [&](const Eigen::Vector3f& p) { return distance_to_box(lo, hi, p) < clearance_m; });
  };
  // Against each wall: a bookshelf and a cabinet where the path leaves room for them.
  for (int f = 0; f < 4; ++f) {
    const int axis = f / 2;  // the wall's normal axis
    const int along = 1 - axis;
    const bool at_max = (f & 1) != 0;
    for (int piece = 0; piece < 2; ++piece) {
      const bool shelf = piece == 0;
      const float depth = shelf ? 0.35f : 0.5f;
      const float width = 1.2f;
      const float u = uni(0.3f, std::max(0.3f, size[along] - width - 0.3f));
      Eigen::Vector3f lo = Eigen::Vector3f::Zero();
      Eigen::Vector3f hi(0.0f, 0.0f, shelf ? 1.9f : 0.9f);
      lo[along] = u;
      hi[along] = u + width;
      lo[axis] = at_max ? size[axis] - depth : 0.0f;
      hi[axis] = at_max ? size[axis] : depth;
      if (!clear(lo, hi)) continue;
      const int front = 2 * axis + (at_max ? 0 : 1);  // the face towards the room
      std::array<bool, 6> hidden{};
      hidden[static_cast<std::size_t>(2 * axis + (at_max ? 1 : 0))] = true;
      hidden[kMinZ] = true;
      if (shelf) {
        add_box(scene, b, lo, hi,
                [front](int face, GrayImage& img, float texel, std::uint32_t seed) {
                  paint_bookshelf_face(face, img, texel, seed, front);
                },
                hidden);
      } else {
        add_box(scene, b, lo, hi,
                [front](int face, GrayImage& img, float texel, std::uint32_t seed) {
                  paint_wood(img, texel, 0.55f, seed);
                  if (face == front) {
                    paint_panel(img, texel, {0.02f, 0.06f, 0.57f, 0.8f}, 0.6f, 0.05f, seed + 1u);
                    paint_panel(img, texel, {0.61f, 0.06f, 0.57f, 0.8f}, 0.6f, 0.05f, seed + 2u);
                  }
                },
                hidden);
      }
    }
  }
  // Free-standing crates and pillars on a 2.5 m grid, in random order, where the path is at least
  // `clearance_m` away; at most 8 (every box costs each ray a slab test).
  std::vector<Eigen::Vector2f> spots;
  for (float y = 1.25f; y < size.y() - 0.5f; y += 2.5f)
    for (float x = 1.25f; x < size.x() - 0.5f; x += 2.5f) spots.emplace_back(x, y);
  for (std::size_t i = spots.size(); i > 1; --i) std::swap(spots[i - 1], spots[g.below(static_cast<std::uint32_t>(i))]);
  int crates = 0;
  for (const Eigen::Vector2f& c : spots) {
    if (crates == 8) break;
    const bool pillar = g.below(4) == 0;
    const float w = pillar ? 0.4f : uni(0.5f, 1.2f);
    const float d = pillar ? 0.4f : uni(0.5f, 1.2f);
    const float h = pillar ? size.z() : uni(0.4f, std::min(2.0f, size.z() - 0.3f));
    const Eigen::Vector3f lo(c.x() - 0.5f * w, c.y() - 0.5f * d, 0.0f);
    const Eigen::Vector3f hi(c.x() + 0.5f * w, c.y() + 0.5f * d, h);
    if (!clear(lo, hi)) continue;
    std::array<bool, 6> hidden{};
    hidden[kMinZ] = true;
    hidden[kMaxZ] = pillar;
    if (pillar)
      add_box(scene, b, lo, hi, [](int, GrayImage& img, float texel, std::uint32_t seed) {
        paint_plaster(img, texel, 0.6f, 0.15f, seed);
      }, hidden);
    else if (crates % 2 == 0)
      add_box(scene, b, lo, hi, paint_printed_face, hidden);
    else
      add_box(scene, b, lo, hi, [](int, GrayImage& img, float texel, std::uint32_t seed) {
        paint_wood(img, texel, 0.5f, seed);
      }, hidden);
    ++crates;
  }
  // Lamps on a grid about 7 m apart, at most 3 x 3 (each one costs every shaded ray); the ceiling
  // is above the path by more than their 6 cm.
  const int nx = std::clamp(static_cast<int>(std::lround(size.x() / 7.0f)), 1, 3);
  const int ny = std::clamp(static_cast<int>(std::lround(size.y() / 7.0f)), 1, 3);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      add_lamp(scene, b, size.x() * (static_cast<float>(i) + 0.5f) / static_cast<float>(nx),
               size.y() * (static_cast<float>(j) + 0.5f) / static_cast<float>(ny));
  // Sunlight through a window, slanted across the floor near the middle.
  scene.sun.origin = Eigen::Vector2f(0.5f * size.x() - 0.6f, 0.5f * size.y() - 0.45f);
  scene.sun.edge_a = Eigen::Vector2f(1.2f, 0.0f);
  scene.sun.edge_b = Eigen::Vector2f(0.4f, 0.9f);
  scene.finish_lighting();
  return scene;
}

}  // namespace ale::render

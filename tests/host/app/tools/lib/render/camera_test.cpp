// The rendered camera's geometry: pinhole projection and rays agree both ways, the sweeper
// mounting looks forward and up, and a marker at a known 3-D point lands where the pinhole model
// says it should.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "app/tools/lib/render/camera.h"
#include "app/tools/lib/render/renderer.h"
#include "app/tools/lib/render/scene.h"

namespace ale::render {
namespace {

TEST(RenderCamera, ProjectAndRayAreInverse) {
  const PinholeCamera cam = PinholeCamera::wide(640, 480);
  EXPECT_DOUBLE_EQ(cam.fx, 320.0);
  EXPECT_DOUBLE_EQ(cam.cx, 319.5);
  for (double u : {0.0, 17.25, 319.5, 639.0})
    for (double v : {0.0, 100.5, 479.0}) {
      const Eigen::Vector3d r = cam.ray(u, v);
      EXPECT_NEAR(r.norm(), 1.0, 1e-12);
      const Eigen::Vector2d uv = cam.project(2.7 * r);
      EXPECT_NEAR(uv.x(), u, 1e-9);
      EXPECT_NEAR(uv.y(), v, 1e-9);
    }
  // A point on the optical axis projects to the principal point; one 1 m right at 2 m depth
  // lands fx / 2 pixels right of it.
  EXPECT_NEAR(cam.project({0.0, 0.0, 3.0}).x(), 319.5, 1e-12);
  EXPECT_NEAR(cam.project({1.0, -0.5, 2.0}).x(), 319.5 + 160.0, 1e-12);
  EXPECT_NEAR(cam.project({1.0, -0.5, 2.0}).y(), 239.5 - 80.0, 1e-12);
}

// The distorted lenses (the daemon's camera model) invert too, over the whole image.
TEST(RenderCamera, DistortedLensesProjectAndRayAreInverse) {
  for (const char* name : {"radtan", "fisheye"}) {
    const Result<PinholeCamera> cam = PinholeCamera::named(name, 640, 480);
    ASSERT_TRUE(cam.ok());
    for (double u : {0.0, 17.25, 325.9, 639.0})
      for (double v : {0.0, 100.5, 479.0}) {
        const Eigen::Vector3d r = cam->ray(u, v);
        ASSERT_NEAR(r.norm(), 1.0, 1e-12) << name << " " << u << " " << v;
        const Eigen::Vector2d uv = cam->project(2.7 * r);
        EXPECT_NEAR(uv.x(), u, 1e-6) << name;
        EXPECT_NEAR(uv.y(), v, 1e-6) << name;
      }
    // The barrel distortion pulls an off-axis point in, towards the principal point.
    const Eigen::Vector2d edge = cam->project({1.0, 0.0, 1.0});
    EXPECT_LT(edge.x() - cam->cx, cam->fx) << name;
  }
  EXPECT_FALSE(PinholeCamera::named("wide", 640, 480).ok());
}

TEST(RenderCamera, SweeperMountLooksForwardAndUp) {
  const Eigen::Matrix3d R = sweeper_R_bc(12.0);
  EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  const Eigen::Vector3d forward = R.col(2);  // optical axis in the body frame
  EXPECT_NEAR(std::atan2(forward.z(), forward.x()) * 180.0 / 3.14159265358979, 12.0, 1e-9);
  EXPECT_NEAR(forward.y(), 0.0, 1e-12);
  EXPECT_NEAR(R.col(0).y(), -1.0, 1e-12);  // image right is the robot's right
  EXPECT_LT(R.col(1).z(), -0.9);           // image down is (mostly) down
}

// Renders a glowing 2 cm cube in an empty room and returns the centroid of the pixels it lights.
Eigen::Vector2d marker_centroid(const PinholeCamera& cam, const Eigen::Matrix3d& R_wc, const Eigen::Vector3d& p_wc,
                                const Eigen::Vector3f& marker, int* count) {
  Scene scene;  // untextured room: black except the marker
  add_marker(scene, marker, 0.02f, 100.0f);
  Renderer renderer(scene, cam, 2);
  std::vector<float> radiance;
  renderer.render(R_wc, p_wc, LightState{}, radiance);
  double sx = 0, sy = 0, sw = 0;
  *count = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const double w = radiance[static_cast<std::size_t>(y * cam.width + x)];
      if (w <= 0.0) continue;
      sx += w * x;
      sy += w * y;
      sw += w;
      ++*count;
    }
  return sw > 0 ? Eigen::Vector2d(sx / sw, sy / sw) : Eigen::Vector2d(-1, -1);
}

TEST(RenderCamera, MarkerLandsWhereThePinholeModelProjectsIt) {
  const PinholeCamera cam = PinholeCamera::wide(320, 240);
  // The sweeper camera at (1, 2.5, 0.09) heading +x, tilted up 12 degrees.
  const Eigen::Matrix3d R_wc = sweeper_R_bc(12.0);
  const Eigen::Vector3d p_wc(1.0, 2.5, 0.09);
  const Eigen::Vector3f markers[] = {{2.5f, 2.5f, 0.4f}, {2.0f, 2.1f, 0.2f}, {3.0f, 3.2f, 0.9f}, {1.8f, 2.9f, 0.05f}};
  for (const Eigen::Vector3f& m : markers) {
    const Eigen::Vector3d p_c = R_wc.transpose() * (m.cast<double>() - p_wc);
    ASSERT_GT(p_c.z(), 0.0);
    const Eigen::Vector2d expected = cam.project(p_c);
    int count = 0;
    const Eigen::Vector2d got = marker_centroid(cam, R_wc, p_wc, m, &count);
    EXPECT_GT(count, 0) << "marker at " << m.transpose() << " not seen";
    // The cube's centroid shifts a little from its centre's projection (we see two or three
    // faces) and the 2x2 sub-pixel grid samples its edges; both stay under half a pixel here.
    EXPECT_NEAR(got.x(), expected.x(), 0.5) << m.transpose();
    EXPECT_NEAR(got.y(), expected.y(), 0.5) << m.transpose();
  }
}

}  // namespace
}  // namespace ale::render

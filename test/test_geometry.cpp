// Back-projection and normals against scenes with known geometry.
#include "synthetic_fixtures.hpp"

#include "risas/geometry.hpp"

#include <gtest/gtest.h>

namespace risas {
namespace {

using test::angleDeg;

using test::pose;

// Share of pixels with an estimated normal within max_deg of the true one,
// over the pixels of `region` (all rendered pixels when empty).
double shareWithin(const FrameGeometry& g, const SyntheticRender& truth, double max_deg, int* counted = nullptr) {
  int total = 0, good = 0;
  for (int r = 0; r < truth.normals.rows; ++r) {
    for (int c = 0; c < truth.normals.cols; ++c) {
      if (!g.hasNormal(r, c)) continue;
      ++total;
      good += angleDeg(g.normal(r, c), truth.normals.at<cv::Vec3f>(r, c)) <= max_deg;
    }
  }
  if (counted) *counted = total;
  return total ? static_cast<double>(good) / total : 0.0;
}

TEST(Geometry, BackProjectionUsesFxAndFy) {
  const Intrinsics K(500.0, 600.0, 30.0, 20.0);
  cv::Mat depth(40, 60, CV_32FC1, cv::Scalar(2.0f));
  const cv::Mat points = backProject(depth, K);
  const cv::Vec3f p = points.at<cv::Vec3f>(35, 50);  // row v = 35, column u = 50
  EXPECT_FLOAT_EQ(p[0], (50 - 30.0f) * 2.0f / 500.0f);
  EXPECT_FLOAT_EQ(p[1], (35 - 20.0f) * 2.0f / 600.0f);
  EXPECT_FLOAT_EQ(p[2], 2.0f);
  depth.at<float>(1, 1) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(std::isnan(backProject(depth, K).at<cv::Vec3f>(1, 1)[2]));
}

TEST(Geometry, SlantedPlaneNormalsWithinTwoDegreesOfMillimetreDepth) {
  SyntheticScene scene;
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  scene.addPlane(pose({0, 0, 1.5}, tilt), 3.0, 3.0, Material{});
  SyntheticRender truth;
  const RgbdFrame frame = test::renderFrame(scene, Eigen::Isometry3d::Identity(), &truth);
  const FrameGeometry g = computeGeometry(frame, GeometryParams());
  int counted = 0;
  EXPECT_GT(shareWithin(g, truth, 2.0, &counted), 0.999);
  EXPECT_GT(shareWithin(g, truth, 1.0), 0.95);
  EXPECT_GT(counted, 0.95 * 640 * 480);
  // Facing the camera: n . p < 0 everywhere.
  const cv::Vec3f n = g.normal(240, 320), p = g.points.at<cv::Vec3f>(240, 320);
  EXPECT_LT(n.dot(p), 0.0f);
}

TEST(Geometry, SphereNormalsWithinFewDegrees) {
  SyntheticScene scene;
  scene.addSphere({0.0, 0.0, 1.2}, 0.3, Material{});
  SyntheticRender truth;
  const RgbdFrame frame = test::renderFrame(scene, Eigen::Isometry3d::Identity(), &truth);
  const FrameGeometry g = computeGeometry(frame, GeometryParams());
  int counted = 0;
  EXPECT_GT(shareWithin(g, truth, 4.0, &counted), 0.95);
  EXPECT_GT(counted, 50000);
}

TEST(Geometry, NormalsDoNotMixSurfacesAcrossADepthJump) {
  // A box 0.5 m in front of a wall: a window straddling the silhouette would
  // tilt the normals of both towards each other by tens of degrees.
  SyntheticScene scene;
  scene.addPlane(pose({0, 0, 2.0}), 3.0, 3.0, Material{});
  scene.addBox(pose({0, 0, 1.4}, Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix()),
               {0.2, 0.2, 0.2}, Material{});
  SyntheticRender truth;
  const RgbdFrame frame = test::renderFrame(scene, Eigen::Isometry3d::Identity(), &truth);
  const FrameGeometry g = computeGeometry(frame, GeometryParams());

  // Pixels within 6 px of the silhouette (a depth jump in the true depth)
  // whose own surface is flat over the whole window: there a normal can only
  // go wrong by taking points from the other side of the jump. (At the box's
  // crease, with no jump, every windowed estimate blends the two faces.)
  const auto trueNormal = [&](int r, int c) { return truth.normals.at<cv::Vec3f>(r, c); };
  const int w = GeometryParams().normal_radius;
  int near_jump = 0, good = 0;
  for (int r = w; r < 480 - w; ++r) {
    for (int c = w; c < 640 - w; ++c) {
      if (!g.hasNormal(r, c)) continue;
      const float z = truth.depth_mm.at<uint16_t>(r, c);
      bool jump = false, flat = true;
      for (int dr = -w; dr <= w; ++dr) {
        for (int dc = -w; dc <= w; ++dc) {
          const bool same_surface = std::abs(truth.depth_mm.at<uint16_t>(r + dr, c + dc) - z) < 200;
          jump |= !same_surface;
          flat &= !same_surface || angleDeg(trueNormal(r + dr, c + dc), trueNormal(r, c)) < 0.1;
        }
      }
      if (!jump || !flat) continue;
      ++near_jump;
      good += angleDeg(g.normal(r, c), trueNormal(r, c)) <= 2.0;
    }
  }
  EXPECT_GT(near_jump, 2000);
  EXPECT_GT(static_cast<double>(good) / near_jump, 0.99);
}

TEST(Geometry, PixelsWithoutDepthHaveNoNormal) {
  cv::Mat depth(48, 64, CV_16UC1, cv::Scalar(1000));
  depth(cv::Rect(20, 10, 8, 8)).setTo(0);
  const RgbdFrame frame(cv::Mat(48, 64, CV_8UC1, cv::Scalar(50)), depth, Intrinsics(60, 60, 32, 24));
  const FrameGeometry g = computeGeometry(frame, GeometryParams());
  EXPECT_FALSE(g.hasPoint(12, 22));
  EXPECT_FALSE(g.hasNormal(12, 22));
  EXPECT_TRUE(g.hasNormal(40, 50));
  EXPECT_LT(angleDeg(g.normal(40, 50), cv::Vec3f(0, 0, -1)), 0.5);
}

}  // namespace
}  // namespace risas

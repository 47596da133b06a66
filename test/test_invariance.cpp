// The descriptor's invariances on rendered scenes with exact ground truth:
// keypoints re-detected at the same 3D point in both views must match their
// counterpart by NNDR (ratio 0.8), most of them.
#include "synthetic_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace risas {
namespace {

using test::CorrespondenceScore;

struct InvarianceTest : ::testing::Test {
  static const SyntheticScene& scene() {
    static const SyntheticScene s = SyntheticScene::demo();
    return s;
  }
  Risas risas;

  CorrespondenceScore score(const Eigen::Isometry3d& camera_a, const Eigen::Isometry3d& camera_b) const {
    return score(risas, camera_a, camera_b);
  }
  static CorrespondenceScore score(const Risas& with, const Eigen::Isometry3d& camera_a,
                                   const Eigen::Isometry3d& camera_b) {
    const Features a = with.extract(test::renderFrame(scene(), camera_a));
    const Features b = with.extract(test::renderFrame(scene(), camera_b));
    return test::scoreCorrespondences(a, b, camera_a.inverse() * camera_b);
  }
};

// Camera roll about the optical axis rotates the image: the dominant
// orientation must turn with it.
TEST_F(InvarianceTest, InPlaneRotation) {
  const Eigen::Isometry3d camera = test::demoCamera();
  for (double degrees : {30.0, 90.0, 145.0, 180.0}) {
    const CorrespondenceScore s = score(camera, test::rolled(camera, degrees));
    std::cout << "roll " << degrees << " deg: " << s.matched << " / " << s.counterparts << " = " << s.rate() << "\n";
    EXPECT_GT(s.counterparts, 80) << degrees << " deg";
    EXPECT_GT(s.rate(), 0.6) << degrees << " deg";
  }
}

// The same on Kinect-like depth, objects 0.4-0.6 m before a wall as in the
// dataset's geometry scenes. The projector's shadow (10-13 px of the wall
// without depth, left of each object) turns with the camera: rolled, a view
// has it on another side of each object, and the keypoints beside it lose or
// gain the samples it hides. Measured over the three seeds, counterparts
// matched: 0.88 / 0.82 / 0.89 at 30 / 90 / 180 degrees; without the shadow
// 0.91 / 0.91 / 0.90 (docs/evaluation.md, "The projector's shadow").
TEST(InvarianceOnKinectDepth, InPlaneRotationWithTheProjectorsShadow) {
  SyntheticScene scene;
  scene.addPlane(test::pose({0, 0, 1.6}), 1.5, 1.2, Material{true, 0.3, 300.0, 21});
  scene.addSphere({-0.15, 0.05, 1.1}, 0.13, Material{true, 0.8, 400.0, 22});
  scene.addBox(test::pose({0.22, -0.05, 1.15}, Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix()),
               {0.08, 0.15, 0.08}, Material{true, 0.5, 600.0, 23});
  scene.addBox(test::pose({0.0, 0.25, 1.2}), {0.3, 0.03, 0.2}, Material{true, 0.4, 500.0, 24});
  const Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  const Risas risas;
  for (double degrees : {30.0, 90.0, 180.0}) {
    CorrespondenceScore total;
    for (const uint64_t seed : {10, 20, 30}) {
      const Features a = risas.extract(test::kinectLikeFrame(scene, camera, seed));
      const Features b = risas.extract(test::kinectLikeFrame(scene, test::rolled(camera, degrees), seed + 1));
      const CorrespondenceScore s = test::scoreCorrespondences(a, b, camera.inverse() * test::rolled(camera, degrees));
      total.counterparts += s.counterparts, total.matched += s.matched;
    }
    std::cout << "roll " << degrees << " deg: " << total.matched << " / " << total.counterparts << " = " << total.rate()
              << "\n";
    EXPECT_GT(total.counterparts, 250) << degrees << " deg";
    EXPECT_GT(total.rate(), 0.75) << degrees << " deg";
  }
}

// The paper's illumination set: I' = 255 (I / 255)^g for square, square
// root, cube and cube root. Intensity ranks survive, so should the matches.
TEST_F(InvarianceTest, MonotonicIntensityChanges) {
  SyntheticRender render;
  const RgbdFrame frame = test::renderFrame(scene(), test::demoCamera(), &render);
  const Features reference = risas.extract(frame);
  for (double g : {2.0, 0.5, 3.0, 1.0 / 3.0}) {
    cv::Mat lut(1, 256, CV_8UC1);
    for (int i = 0; i < 256; ++i) lut.at<uchar>(i) = cv::saturate_cast<uchar>(255.0 * std::pow(i / 255.0, g));
    cv::Mat changed;
    cv::LUT(render.bgr, lut, changed);
    const Features f = risas.extract(RgbdFrame(changed, render.depth_mm, syntheticIntrinsics()));
    const CorrespondenceScore s = test::scoreCorrespondences(reference, f, Eigen::Isometry3d::Identity());
    std::cout << "gamma " << g << ": " << s.matched << " / " << s.counterparts << " = " << s.rate() << "\n";
    // Cube and cube root merge dozens of 8-bit levels into ties, which moves
    // rank groups, the rank centroid (theta) and the corners a little: 0.64
    // at worst, measured (0.70 with the paper's shape orientation, which
    // matches worse across viewpoints; docs/evaluation.md).
    EXPECT_GT(s.counterparts, 100) << "gamma " << g;
    EXPECT_GT(s.rate(), 0.6) << "gamma " << g;
  }
}

// Moving the camera back along its axis: the patch covers the same surface
// at every distance (support_radius), so the descriptors stay alike. The
// paper's pixel radius (constant below 2 m) is the baseline it must beat.
TEST_F(InvarianceTest, ScaleChangeFromMovingTheCameraBack) {
  RisasParams paper_radius;
  paper_radius.descriptor.support_radius = 0.0;
  const Risas baseline(paper_radius);
  for (double factor : {1.2, 1.4}) {
    const Eigen::Isometry3d near = test::demoCamera(1.2), far = test::demoCamera(1.2 * factor);
    const CorrespondenceScore s = score(near, far), paper = score(baseline, near, far);
    std::cout << "distance x" << factor << ": " << s.matched << " / " << s.counterparts << " = " << s.rate()
              << " (paper's pixel radius: " << paper.rate() << ")\n";
    // Measured 0.83 and 0.75 (the paper's pixel radius: 0.68 and 0.25).
    EXPECT_GT(s.counterparts, 100) << "x" << factor;
    EXPECT_GT(s.rate(), 0.4) << "x" << factor;
    EXPECT_GT(s.rate(), paper.rate() + 0.1) << "x" << factor;
  }
}

// Near the camera a patch's samples lie several pixels apart (3 px at
// 0.6 m): read from the raw grey image they alias the surface's fine
// texture, and what they see depends on where the sample grid falls. Read
// from the pyramid level blurred in proportion to their spacing
// (descriptor.sample_blur) they see the same smoothed pattern at both
// distances. The detector is the same, so both see the same counterparts.
// Both with the paper's eight rank groups: the aliasing moves a sample's
// grey across the finer groups' bounds; on this rendered texture the
// defaults' four groups absorb it (670 against 674 matched), on the
// dataset's scale pairs the blur still adds 12 % (texture) and 4 %
// (geometry) correct matches to them (docs/evaluation.md, "The
// descriptor's layout").
TEST_F(InvarianceTest, SamplesReadAtTheirOwnScaleMatchAcrossAScaleChange) {
  RisasParams blurred_params;
  blurred_params.descriptor.n_bin = 8, blurred_params.descriptor.n_ring = 1;
  RisasParams raw_params = blurred_params;
  raw_params.descriptor.sample_blur = 0.0;
  const Risas blurred(blurred_params), raw(raw_params);
  CorrespondenceScore blurred_total, raw_total;
  for (double near_distance : {0.6, 0.8, 1.2}) {
    for (double factor : {1.4, 2.0}) {
      const Eigen::Isometry3d near = test::demoCamera(near_distance), far = test::demoCamera(near_distance * factor);
      const CorrespondenceScore s = score(blurred, near, far), r = score(raw, near, far);
      std::cout << near_distance << " m, distance x" << factor << ": " << s.matched << " / " << s.counterparts
                << " (raw grey: " << r.matched << " / " << r.counterparts << ")\n";
      EXPECT_EQ(s.counterparts, r.counterparts);
      blurred_total.matched += s.matched, blurred_total.counterparts += s.counterparts;
      raw_total.matched += r.matched, raw_total.counterparts += r.counterparts;
    }
  }
  // Measured 613 against 581 of 921 counterparts: ahead at all six settings.
  EXPECT_GT(blurred_total.matched, raw_total.matched + 10);
}

// The camera moved back along its axis does not roll: a surface point's
// theta must stay. The intensity centroid of the frame's own grey image
// turns with the fine texture the farther view no longer resolves;
// descriptor.gradient_orientation reads the gradients at the patch's own
// scale and holds theta (docs/evaluation.md, "The orientation across a
// change of distance").
TEST_F(InvarianceTest, GradientOrientationHoldsThetaAcrossAScaleChange) {
  RisasParams centroid_params, gradient_params;
  centroid_params.descriptor.gradient_orientation = false;
  gradient_params.descriptor.gradient_orientation = true;
  const Risas centroid_method(centroid_params), gradient(gradient_params);
  const auto thetaErrors = [&](const Risas& method) {
    std::vector<double> errors;
    for (double near_distance : {0.6, 0.8, 1.2}) {
      for (double factor : {1.4, 2.0}) {
        const Eigen::Isometry3d near = test::demoCamera(near_distance), far = test::demoCamera(near_distance * factor);
        const Features a = method.extract(test::renderFrame(scene(), near));
        const Features b = method.extract(test::renderFrame(scene(), far));
        const Eigen::Isometry3d a_T_b = near.inverse() * far;
        for (size_t i = 0; i < b.geometry.size(); ++i) {
          const cv::Point3f& p = b.geometry[i].point;
          const Eigen::Vector3d q = a_T_b * Eigen::Vector3d(p.x, p.y, p.z);
          for (size_t j = 0; j < a.geometry.size(); ++j) {
            const cv::Point3f& r = a.geometry[j].point;
            if ((Eigen::Vector3d(r.x, r.y, r.z) - q).norm() > 0.005) continue;
            errors.push_back(std::abs(std::remainder(b.keypoints[i].angle - a.keypoints[j].angle, 360.0)));
            break;
          }
        }
      }
    }
    std::sort(errors.begin(), errors.end());
    return errors;
  };
  const std::vector<double> centroid = thetaErrors(centroid_method), gradients = thetaErrors(gradient);
  const auto share_above = [](const std::vector<double>& e, double degrees) {
    return static_cast<double>(std::count_if(e.begin(), e.end(), [&](double x) { return x > degrees; })) / e.size();
  };
  ASSERT_GT(centroid.size(), 200u);
  ASSERT_GT(gradients.size(), 200u);
  std::cout << "theta error, median / share above 20 deg: centroid " << centroid[centroid.size() / 2] << " / "
            << share_above(centroid, 20.0) << " (" << centroid.size() << "), gradients "
            << gradients[gradients.size() / 2] << " / " << share_above(gradients, 20.0) << " (" << gradients.size()
            << ")\n";
  // Measured: medians 4.1 and 1.5 degrees; above 20 degrees 5.1 % and 6.8 %
  // (a corner's two edges make two peaks, and the highest can change).
  EXPECT_LT(gradients[gradients.size() / 2], 0.6 * centroid[centroid.size() / 2]);
  EXPECT_LT(gradients[gradients.size() / 2], 2.5);
  EXPECT_LT(share_above(gradients, 20.0), share_above(centroid, 20.0) + 0.04);
}

}  // namespace
}  // namespace risas

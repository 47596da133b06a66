// Helpers shared by the unit tests: synthetic frames and ground-truth
// correspondence between two renders of one scene.
#pragma once

#include "risas/matcher.hpp"
#include "risas/risas.hpp"
#include "risas/synthetic_scene.hpp"

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace risas::test {

inline const cv::Size kVga(640, 480);

inline Eigen::Isometry3d pose(const Eigen::Vector3d& t, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

inline RgbdFrame renderFrame(const SyntheticScene& scene, const Eigen::Isometry3d& world_T_camera,
                             SyntheticRender* render_out = nullptr) {
  SyntheticRender render = scene.render(syntheticIntrinsics(), kVga, world_T_camera);
  RgbdFrame frame(render.bgr, render.depth_mm, syntheticIntrinsics());
  if (render_out) *render_out = render;
  return frame;
}

// Kinect-like depth from a rendered one (metres, NaN where none): the
// disparity quantised to 1/8 pixel (f b = 43.5 px m, so depth steps of
// z^2 / 348 m: 3 mm at 1 m, 12 mm at 2 m), noise growing with z^2 (sigma
// 1.5 mm at 1 m) and correlated over a few pixels, the projector's shadow
// (projectorShadow), no depth within 2 px of a jump over 5 cm (the mixed
// pixels at silhouettes), and 2 % random holes. The noise is white noise
// blurred by a Gaussian of kKinectNoiseCorrelationPx: on a real Kinect's
// floor at 1.2 m (fr3/cabinet) the depth's residual from its plane
// correlates 0.86 / 0.74 / 0.59 at 1 / 2 / 4 px, and the normals there are
// off by a median 5.4°; white noise of the same sigma gives 0.00 and 1.2°,
// this model 0.87 / 0.74 / 0.51 and 5.7° (docs/evaluation.md, "Normals over
// a window of fixed metric size").
inline constexpr double kKinectNoiseCorrelationPx = 3.0;
inline constexpr double kKinectFocalBaselinePxM = 43.5;

// Where the projector's pattern does not reach: a Kinect measures depth only
// where the IR camera sees the projected pattern, and its projector sits
// 7.5 cm to the camera's +x. A surface point the camera sees at column u and
// depth z lies at column u - fb / z in the projector's view (rows agree);
// a point is in the shadow when some point to its right on the row lies at
// or left of it in the projector's view and nearer: the two are on one
// projector ray, and the nearer one takes the pattern. So the shadow lies on
// the far surface to the left of each nearer object, fb (1/z_near - 1/z_far)
// pixels wide: 14 px for a box 1 m away before a wall 1.5 m away. It turns
// with the camera, not with the scene (the dataset's rotate sequences show
// it).
inline cv::Mat projectorShadow(const cv::Mat& depth) {
  cv::Mat shadow(depth.size(), CV_8U, cv::Scalar(0));
  for (int v = 0; v < depth.rows; ++v) {
    const float* z = depth.ptr<float>(v);
    double leftmost = std::numeric_limits<double>::infinity();  // projector column of the row's right part
    for (int u = depth.cols - 1; u >= 0; --u) {
      if (!(z[u] > 0.0f)) continue;
      const double projector_u = u - kKinectFocalBaselinePxM / z[u];
      if (projector_u >= leftmost + 0.5) shadow.at<uchar>(v, u) = 255;
      leftmost = std::min(leftmost, projector_u);
    }
  }
  return shadow;
}

inline cv::Mat kinectLikeDepth(const cv::Mat& depth, uint64_t seed) {
  cv::Mat out = depth.clone();
  cv::RNG rng(seed);
  // Unit-variance correlated noise: a Gaussian kernel g (1D, sum 1) leaves
  // white noise a variance of (sum g_i^2)^2.
  const int ksize = 2 * static_cast<int>(std::ceil(4.0 * kKinectNoiseCorrelationPx)) + 1;
  const cv::Mat g = cv::getGaussianKernel(ksize, kKinectNoiseCorrelationPx, CV_64F);
  cv::Mat noise(depth.size(), CV_32F);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(noise, noise, cv::Size(ksize, ksize), kKinectNoiseCorrelationPx, kKinectNoiseCorrelationPx,
                   cv::BORDER_REFLECT);
  noise /= g.dot(g);
  const auto jump = [&](int v, int u) {
    const float z = depth.at<float>(v, u);
    for (int dv = -2; dv <= 2; ++dv) {
      for (int du = -2; du <= 2; ++du) {
        const int y = std::clamp(v + dv, 0, depth.rows - 1), x = std::clamp(u + du, 0, depth.cols - 1);
        if (!(std::abs(depth.at<float>(y, x) - z) <= 0.05f)) return true;  // a jump or a hole
      }
    }
    return false;
  };
  const cv::Mat shadow = projectorShadow(depth);
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      float& z = out.at<float>(v, u);
      if (std::isnan(z)) continue;
      if (shadow.at<uchar>(v, u) || jump(v, u) || rng.uniform(0.0, 1.0) < 0.02) {
        z = NAN;
        continue;
      }
      const double noisy = z + 0.0015 * z * z * noise.at<float>(v, u);
      const double disparity = std::round(kKinectFocalBaselinePxM / noisy * 8.0) / 8.0;
      z = static_cast<float>(kKinectFocalBaselinePxM / disparity);
    }
  }
  return out;
}

// A rendered view as a Kinect shows it: the grey image's contrast about
// 128 scaled by `contrast`, grey noise of one level, and kinectLikeDepth.
inline RgbdFrame kinectLikeFrame(const SyntheticScene& scene, const Eigen::Isometry3d& world_T_camera, uint64_t seed,
                                 double contrast = 1.0, SyntheticRender* render_out = nullptr) {
  const RgbdFrame clean = renderFrame(scene, world_T_camera, render_out);
  cv::Mat noise(clean.size(), CV_32F), grey;
  cv::RNG(seed).fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  clean.gray().convertTo(grey, CV_32F);
  grey = 128.0 + contrast * (grey - 128.0) + noise;
  grey.convertTo(grey, CV_8U);
  return RgbdFrame(grey, kinectLikeDepth(clean.depth(), seed), clean.intrinsics());
}

// The camera of the invariance tests: looking down at the demo scene.
inline Eigen::Isometry3d demoCamera(double distance = 1.4) {
  const Eigen::Vector3d target(0.0, 0.05, 0.15);
  const Eigen::Vector3d direction = Eigen::Vector3d(0.0, -1.0, 0.75).normalized();
  return lookAt(target + distance * direction, target);
}

// The same camera rolled about its optical axis by `degrees`.
inline Eigen::Isometry3d rolled(const Eigen::Isometry3d& world_T_camera, double degrees) {
  Eigen::Isometry3d T = world_T_camera;
  T.linear() = world_T_camera.linear() * Eigen::AngleAxisd(degrees * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

// Where a world point lands in the synthetic camera at world_T_camera, in pixels.
inline cv::Point2f projectInto(const Eigen::Isometry3d& world_T_camera, const Eigen::Vector3d& world_point) {
  const Eigen::Vector3d p = world_T_camera.inverse() * world_point;
  return syntheticIntrinsics().project(
      cv::Point3f(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
}

inline double angleDeg(const cv::Vec3f& a, const cv::Vec3f& b) {
  const double c = a.dot(b) / (cv::norm(a) * cv::norm(b));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}

struct CorrespondenceScore {
  int counterparts = 0;  // keypoints of B re-detected in A at the same 3D point
  int matched = 0;       // of those, matched to that very keypoint by NNDR
  double rate() const { return counterparts ? static_cast<double>(matched) / counterparts : 0.0; }
};

// For every feature of B whose 3D point, moved into A's frame by A_T_B, lies
// within `tolerance` metres of a feature of A, checks whether NNDR matching of
// B's descriptors against all of A's picks that feature.
inline CorrespondenceScore scoreCorrespondences(const Features& a, const Features& b, const Eigen::Isometry3d& A_T_B,
                                                double ratio = 0.8, double tolerance = 0.01) {
  MatchParams params;
  params.ratio = ratio;
  const std::vector<cv::DMatch> matches = matchDescriptors(b.descriptors, a.descriptors, params);
  std::vector<int> match_of_b(b.keypoints.size(), -1);
  for (const cv::DMatch& m : matches) match_of_b[static_cast<size_t>(m.queryIdx)] = m.trainIdx;

  CorrespondenceScore score;
  for (size_t i = 0; i < b.geometry.size(); ++i) {
    const cv::Point3f& p = b.geometry[i].point;
    const Eigen::Vector3d q = A_T_B * Eigen::Vector3d(p.x, p.y, p.z);
    int nearest = -1;
    double best = tolerance;
    for (size_t j = 0; j < a.geometry.size(); ++j) {
      const cv::Point3f& r = a.geometry[j].point;
      const double d = (Eigen::Vector3d(r.x, r.y, r.z) - q).norm();
      if (d < best) {
        best = d;
        nearest = static_cast<int>(j);
      }
    }
    if (nearest < 0) continue;
    ++score.counterparts;
    score.matched += match_of_b[i] == nearest;
  }
  return score;
}

// An untextured box on an untextured floor, unlit: the grey image is one
// constant, so every keypoint must come from the shape channel. (Lit, its
// faces are shaded: setLighting, setLightDirection.)
struct UntexturedBox {
  SyntheticScene scene;
  Eigen::Isometry3d camera;
  Eigen::Isometry3d box_pose;
  Eigen::Vector3d half{0.15, 0.1, 0.12};
  // The camera (camera = lookAt(eye, target)), 1.2 m from the box.
  const Eigen::Vector3d eye{0.2, -0.9, 0.8}, target{0.0, 0.0, 0.1};

  UntexturedBox() {
    const Material plain{false, 0.5, 0.0, 0};
    scene.addPlane(pose({0, 0, 0}), 5.0, 5.0, plain);
    box_pose = pose({0, 0, half.z()}, Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix());
    scene.addBox(box_pose, half, plain);
    scene.setLighting(false);
    camera = lookAt(eye, target);
  }

  // Corner i of the box (bits: +x, +y, +z) in the world, in camera coordinates and in pixels.
  Eigen::Vector3d worldPoint(int corner) const {
    const Eigen::Vector3d local(corner & 1 ? half.x() : -half.x(), corner & 2 ? half.y() : -half.y(),
                                corner & 4 ? half.z() : -half.z());
    return box_pose * local;
  }
  Eigen::Vector3d cameraPoint(int corner) const { return camera.inverse() * worldPoint(corner); }
  cv::Point2f project(int corner) const { return projectInto(camera, worldPoint(corner)); }

  // Distance in pixels from p to the nearest projected edge of the box.
  double distanceToEdges(const cv::Point2f& p) const {
    double best = 1e9;
    for (int a = 0; a < 8; ++a) {
      for (int bit : {1, 2, 4}) {
        if (a & bit) continue;
        const cv::Point2f s = project(a), e = project(a | bit);
        const cv::Point2f d = e - s;
        const float t = std::clamp((p - s).dot(d) / d.dot(d), 0.0f, 1.0f);
        best = std::min(best, cv::norm(p - (s + t * d)));
      }
    }
    return best;
  }

  // The box's corners that the camera sees, in pixels.
  std::vector<cv::Point2f> visibleCorners(const SyntheticRender& render) const {
    std::vector<cv::Point2f> corners;
    for (int i = 0; i < 8; ++i) {
      const double z_mm = cameraPoint(i).z() * 1000.0;
      const cv::Point2f px = project(i);
      const int u = cvRound(px.x), v = cvRound(px.y);
      if (u < 3 || v < 3 || u >= 637 || v >= 477) continue;
      // Visible when some pixel right around it shows the corner's depth (on a
      // silhouette the rounded pixel itself may show the floor behind).
      bool visible = false;
      for (int dv = -3; dv <= 3; ++dv) {
        for (int du = -3; du <= 3; ++du) {
          visible |= std::abs(render.depth_mm.at<uint16_t>(v + dv, u + du) - z_mm) < 15.0;
        }
      }
      if (visible) corners.push_back(px);
    }
    return corners;
  }
};

}  // namespace risas::test

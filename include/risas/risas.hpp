// RISAS: detector + descriptor over one RGB-D frame, the common entry point.
//
//   #include <risas/risas.hpp>
//   risas::RgbdFrame frame(bgr, depth_mm, risas::Intrinsics(fx, fy, cx, cy));
//   cv::Ptr<risas::Risas> risas = risas::Risas::create();
//   std::vector<cv::KeyPoint> keypoints;
//   cv::Mat descriptors;                      // N x 64 CV_32F (the paper's n_vec: N x 192), NORM_L2
//   std::vector<risas::KeypointGeometry> info; // 3D point, normal, radius
//   risas->detectAndCompute(frame, cv::Mat(), keypoints, descriptors, &info);
//
// Why not a cv::Feature2D: its detect/compute take one image and no
// intrinsics, and RISAS needs colour, depth and K together; hiding depth in
// member state would break the reentrancy of a shared cv::Ptr. The outputs
// are Feature2D's, so cv::BFMatcher, cv::drawMatches, cv::KeyPointsFilter
// and cv::FileStorage work unchanged.
#pragma once

#include "risas/features.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <opencv2/core.hpp>

#include <memory>
#include <vector>

namespace risas {

// As cv::ORB over its hidden ORB_Impl: the stages (geometry, detector,
// descriptor) are the library's inside, not its interface.
class Risas {
 public:
  // std::invalid_argument when params are out of range (RisasParams::validate).
  explicit Risas(const RisasParams& params = RisasParams());
  static cv::Ptr<Risas> create(const RisasParams& params = RisasParams());

  // Geometry once, then detector and descriptor on it. mask: CV_8UC1 of the
  // frame's size, or empty. Const and reentrant.
  void detectAndCompute(const RgbdFrame& frame, const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints,
                        cv::Mat& descriptors, std::vector<KeypointGeometry>* info = nullptr) const;
  // The same, gathered into one Features value.
  Features extract(const RgbdFrame& frame, const cv::Mat& mask = cv::Mat()) const;
  void detect(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, const cv::Mat& mask = cv::Mat()) const;
  // Like cv::Feature2D::compute: keypoints that cannot be described are removed.
  void compute(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors,
               std::vector<KeypointGeometry>* info = nullptr) const;

  const RisasParams& params() const;
  int descriptorSize() const;  // params().descriptor.dimension()
  int descriptorType() const;  // CV_32F
  int defaultNorm() const;     // cv::NORM_L2

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;  // immutable: copies share it
};

}  // namespace risas

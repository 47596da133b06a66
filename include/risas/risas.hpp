// RISAS: detector + descriptor over one RGB-D frame, the common entry point.
//
//   #include <risas/risas.hpp>
//   risas::RgbdFrame frame(bgr, depth_mm, risas::Intrinsics(fx, fy, cx, cy));
//   cv::Ptr<risas::Risas> risas = risas::Risas::create();
//   std::vector<cv::KeyPoint> keypoints;
//   cv::Mat descriptors;                      // N x 192 CV_32F, NORM_L2
//   std::vector<risas::KeypointGeometry> info; // 3D point, normal, radius
//   risas->detectAndCompute(frame, cv::Mat(), keypoints, descriptors, &info);
//
// Why not a cv::Feature2D: its detect/compute take one image and no
// intrinsics, and RISAS needs colour, depth and K together; hiding depth in
// member state would break the reentrancy of a shared cv::Ptr. The outputs
// are Feature2D's, so cv::BFMatcher, cv::drawMatches, cv::KeyPointsFilter
// and cv::FileStorage work unchanged.
#pragma once

#include "risas/descriptor.hpp"
#include "risas/detector.hpp"
#include "risas/features.hpp"
#include "risas/geometry.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace risas {

class Risas {
 public:
  explicit Risas(const RisasParams& params = RisasParams());
  static cv::Ptr<Risas> create(const RisasParams& params = RisasParams());

  // Geometry once, then detector and descriptor on it. mask: CV_8UC1 of the
  // frame's size, or empty. Const and reentrant.
  void detectAndCompute(const RgbdFrame& frame, const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints,
                        cv::Mat& descriptors, std::vector<KeypointGeometry>* info = nullptr) const;
  // The same, gathered into one Features value.
  Features extract(const RgbdFrame& frame, const cv::Mat& mask = cv::Mat()) const;
  void detect(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, const cv::Mat& mask = cv::Mat()) const;
  void compute(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors,
               std::vector<KeypointGeometry>* info = nullptr) const;

  FrameGeometry computeGeometry(const RgbdFrame& frame) const;
  // Into geometry, reusing its buffers (see geometry.hpp).
  void computeGeometry(const RgbdFrame& frame, FrameGeometry& geometry) const;
  const Detector& detector() const { return detector_; }
  const Descriptor& descriptor() const { return descriptor_; }
  const RisasParams& params() const { return params_; }

  int descriptorSize() const { return descriptor_.descriptorSize(); }
  int descriptorType() const { return descriptor_.descriptorType(); }
  int defaultNorm() const { return descriptor_.defaultNorm(); }

 private:
  RisasParams params_;
  Detector detector_;
  Descriptor descriptor_;
};

}  // namespace risas

// The RISAS descriptor (paper III-B), computed for given keypoints.
#pragma once

#include "risas/encoding.hpp"
#include "risas/features.hpp"
#include "risas/geometry.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace risas {

class Descriptor {
 public:
  explicit Descriptor(const DescriptorParams& params = DescriptorParams());

  // Describes each keypoint (paper III-B): scale s from depth (eq. 3), initial
  // radius R (eq. 4), background elimination (eq. 5), ellipse radius R-bar,
  // dominant orientation theta (eq. 7), histogram encoding. Like
  // cv::Feature2D::compute, keypoints that cannot be described (no depth or
  // normal, shapeless patch, too little foreground) are removed; the others
  // get size = 2 R-bar and angle = theta in degrees [0, 360). descriptors is
  // N x dimension() CV_32F, row i for keypoints[i]; `info`, if given, gets
  // each keypoint's 3D point, normal and support radius. Const and reentrant;
  // keypoints are described in parallel.
  void compute(const RgbdFrame& frame, const FrameGeometry& geometry, std::vector<cv::KeyPoint>& keypoints,
               cv::Mat& descriptors, std::vector<KeypointGeometry>* info = nullptr) const;

  int descriptorSize() const { return params_.dimension(); }
  int descriptorType() const { return CV_32F; }
  int defaultNorm() const { return cv::NORM_L2; }
  const DescriptorParams& params() const { return params_; }

 private:
  DescriptorParams params_;
  PatchEncoder encoder_;
};

}  // namespace risas

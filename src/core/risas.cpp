#include "risas/risas.hpp"

namespace risas {

Risas::Risas(const RisasParams& params)
    : params_(params), detector_(params.detector), descriptor_(params.descriptor) {
  params_.validate();
}

cv::Ptr<Risas> Risas::create(const RisasParams& params) { return cv::makePtr<Risas>(params); }

namespace {

// The geometry of the frame in hand, one per thread, its buffers reused from
// frame to frame. Only the calls below use it, and none keeps it past its
// return, so reusing it can change no result.
FrameGeometry& threadGeometry() {
  thread_local FrameGeometry geometry;
  return geometry;
}

}  // namespace

FrameGeometry Risas::computeGeometry(const RgbdFrame& frame) const {
  return risas::computeGeometry(frame, params_.geometry);
}

void Risas::computeGeometry(const RgbdFrame& frame, FrameGeometry& geometry) const {
  risas::computeGeometry(frame, params_.geometry, geometry);
}

void Risas::detectAndCompute(const RgbdFrame& frame, const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints,
                             cv::Mat& descriptors, std::vector<KeypointGeometry>* info) const {
  FrameGeometry& geometry = threadGeometry();
  computeGeometry(frame, geometry);
  detector_.detect(frame, geometry, keypoints, mask);
  descriptor_.compute(frame, geometry, keypoints, descriptors, info);
}

Features Risas::extract(const RgbdFrame& frame, const cv::Mat& mask) const {
  Features features;
  detectAndCompute(frame, mask, features.keypoints, features.descriptors, &features.geometry);
  return features;
}

void Risas::detect(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, const cv::Mat& mask) const {
  FrameGeometry& geometry = threadGeometry();
  computeGeometry(frame, geometry);
  detector_.detect(frame, geometry, keypoints, mask);
}

void Risas::compute(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors,
                    std::vector<KeypointGeometry>* info) const {
  FrameGeometry& geometry = threadGeometry();
  computeGeometry(frame, geometry);
  descriptor_.compute(frame, geometry, keypoints, descriptors, info);
}

}  // namespace risas

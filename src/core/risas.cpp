#include "risas/risas.hpp"

namespace risas {

Risas::Risas(const RisasParams& params)
    : params_(params), detector_(params.detector), descriptor_(params.descriptor) {
  params_.validate();
}

cv::Ptr<Risas> Risas::create(const RisasParams& params) { return cv::makePtr<Risas>(params); }

FrameGeometry Risas::computeGeometry(const RgbdFrame& frame) const {
  return risas::computeGeometry(frame, params_.geometry);
}

void Risas::detectAndCompute(const RgbdFrame& frame, const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints,
                             cv::Mat& descriptors, std::vector<KeypointGeometry>* info) const {
  const FrameGeometry geometry = computeGeometry(frame);
  detector_.detect(frame, geometry, keypoints, mask);
  descriptor_.compute(frame, geometry, keypoints, descriptors, info);
}

Features Risas::extract(const RgbdFrame& frame, const cv::Mat& mask) const {
  Features features;
  detectAndCompute(frame, mask, features.keypoints, features.descriptors, &features.geometry);
  return features;
}

void Risas::detect(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, const cv::Mat& mask) const {
  detector_.detect(frame, computeGeometry(frame), keypoints, mask);
}

void Risas::compute(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors,
                    std::vector<KeypointGeometry>* info) const {
  descriptor_.compute(frame, computeGeometry(frame), keypoints, descriptors, info);
}

}  // namespace risas

#include "risas/risas.hpp"

namespace risas {

Risas::Risas(const RisasParams& params)
    : params_(params), detector_(params.detector), descriptor_(params.descriptor) {
  params_.validate();
}

cv::Ptr<Risas> Risas::create(const RisasParams& params) { return cv::makePtr<Risas>(params); }

namespace {

// Calls use(geometry) with the frame's geometry in this thread's buffers,
// reused from frame to frame (none of the calls below keeps it past its
// return). The geometry shares the frame's depth; it is let go afterwards,
// also after an exception, so that the caller's frame is not held until the
// next call.
template <class Use>
void withGeometry(const RgbdFrame& frame, const GeometryParams& params, Use&& use) {
  thread_local FrameGeometry geometry;
  struct ReleaseDepth {  // also when use throws (bad input)
    ~ReleaseDepth() { geometry.depth.release(); }
  } release;
  computeGeometry(frame, params, geometry);
  use(geometry);
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
  withGeometry(frame, params_.geometry, [&](const FrameGeometry& geometry) {
    detector_.detect(frame, geometry, keypoints, mask);
    descriptor_.compute(frame, geometry, keypoints, descriptors, info);
  });
}

Features Risas::extract(const RgbdFrame& frame, const cv::Mat& mask) const {
  Features features;
  detectAndCompute(frame, mask, features.keypoints, features.descriptors, &features.geometry);
  return features;
}

void Risas::detect(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, const cv::Mat& mask) const {
  withGeometry(frame, params_.geometry,
               [&](const FrameGeometry& geometry) { detector_.detect(frame, geometry, keypoints, mask); });
}

void Risas::compute(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors,
                    std::vector<KeypointGeometry>* info) const {
  withGeometry(frame, params_.geometry, [&](const FrameGeometry& geometry) {
    descriptor_.compute(frame, geometry, keypoints, descriptors, info);
  });
}

}  // namespace risas

#include "risas/risas.hpp"

#include "risas/descriptor.hpp"
#include "risas/detector.hpp"
#include "risas/geometry.hpp"
#include "risas/workspace.hpp"

namespace risas {

struct Risas::Impl {
  RisasParams params;
  Detector detector;
  Descriptor descriptor;
  explicit Impl(const RisasParams& p) : params(p), detector(p.detector), descriptor(p.descriptor) { params.validate(); }
};

Risas::Risas(const RisasParams& params) : impl_(std::make_shared<const Impl>(params)) {}

cv::Ptr<Risas> Risas::create(const RisasParams& params) { return cv::makePtr<Risas>(params); }

namespace {

// The frame's geometry between the facade's stages.
struct FacadeGeometry {
  FrameGeometry geometry;
};

// Calls use(geometry) with the frame's geometry in this thread's buffers,
// reused from frame to frame (none of the calls below keeps it past its
// return). The geometry shares the frame's depth; it is let go afterwards,
// also after an exception, so that the caller's frame is not held until the
// next call.
template <class Use>
void withGeometry(const RgbdFrame& frame, const GeometryParams& params, Use&& use) {
  FrameGeometry& geometry = Workspace::ofThisThread().get<FacadeGeometry>().geometry;
  struct ReleaseDepth {  // also when use throws (bad input)
    FrameGeometry& geometry;
    ~ReleaseDepth() { geometry.depth.release(); }
  } release{geometry};
  computeGeometry(frame, params, geometry);
  use(geometry);
}

}  // namespace

void Risas::detectAndCompute(const RgbdFrame& frame, const cv::Mat& mask, std::vector<cv::KeyPoint>& keypoints,
                             cv::Mat& descriptors, std::vector<KeypointGeometry>* info) const {
  withGeometry(frame, impl_->params.geometry, [&](const FrameGeometry& geometry) {
    impl_->detector.detect(frame, geometry, keypoints, mask);
    impl_->descriptor.compute(frame, geometry, keypoints, descriptors, info);
  });
}

Features Risas::extract(const RgbdFrame& frame, const cv::Mat& mask) const {
  Features features;
  detectAndCompute(frame, mask, features.keypoints, features.descriptors, &features.geometry);
  features.descriptor_layout = impl_->params.descriptor.layout();
  return features;
}

void Risas::detect(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, const cv::Mat& mask) const {
  withGeometry(frame, impl_->params.geometry,
               [&](const FrameGeometry& geometry) { impl_->detector.detect(frame, geometry, keypoints, mask); });
}

void Risas::compute(const RgbdFrame& frame, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors,
                    std::vector<KeypointGeometry>* info) const {
  withGeometry(frame, impl_->params.geometry, [&](const FrameGeometry& geometry) {
    impl_->descriptor.compute(frame, geometry, keypoints, descriptors, info);
  });
}

const RisasParams& Risas::params() const { return impl_->params; }
int Risas::descriptorSize() const { return impl_->descriptor.descriptorSize(); }
int Risas::descriptorType() const { return impl_->descriptor.descriptorType(); }
int Risas::defaultNorm() const { return impl_->descriptor.defaultNorm(); }

}  // namespace risas

// Pinhole intrinsics of the registered RGB-D pair.
#pragma once

#include <opencv2/core.hpp>

namespace risas {

struct Intrinsics {
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;

  Intrinsics() = default;
  Intrinsics(double fx_, double fy_, double cx_, double cy_) : fx(fx_), fy(fy_), cx(cx_), cy(cy_) {}
  // From a 3x3 camera matrix; throws InputError unless it is a pinhole K
  // (zero skew, last row 0 0 1).
  static Intrinsics fromMatrix(const cv::Matx33d& K);
  cv::Matx33d matrix() const;

  // Throws InputError when a focal length is not finite or outside
  // [kMinFocal, kMaxFocal] pixels, or the principal point is not finite;
  // given the image size, also when a focal length is outside
  // [kMinFocalPerSide, kMaxFocalPerSide] times the image's larger side (a
  // field of view of about 175 down to 1 degree) or the principal point
  // lies outside the image.
  static constexpr double kMinFocal = 1.0, kMaxFocal = 1e6;
  static constexpr double kMinFocalPerSide = 0.02, kMaxFocalPerSide = 50.0;
  void validate() const;
  void validate(cv::Size image_size) const;

  // Pixel (u, v) at depth z (metres, along the optical axis) -> camera point.
  cv::Point3f backProject(float u, float v, float z) const {
    return {static_cast<float>((u - cx) * z / fx), static_cast<float>((v - cy) * z / fy), z};
  }
  cv::Point2f project(const cv::Point3f& p) const {
    return {static_cast<float>(fx * p.x / p.z + cx), static_cast<float>(fy * p.y / p.z + cy)};
  }
};

}  // namespace risas

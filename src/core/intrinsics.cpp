#include "risas/intrinsics.hpp"

#include "risas/errors.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace risas {

Intrinsics Intrinsics::fromMatrix(const cv::Matx33d& K) {
  const bool pinhole = K(0, 1) == 0.0 && K(1, 0) == 0.0 && K(2, 0) == 0.0 && K(2, 1) == 0.0 &&
                       K(2, 2) == 1.0;
  if (!pinhole) {
    std::ostringstream msg;  // one line: the matrix row by row
    msg << "camera matrix is not a pinhole K [fx 0 cx; 0 fy cy; 0 0 1]: [" << K(0, 0) << " " << K(0, 1) << " "
        << K(0, 2) << "; " << K(1, 0) << " " << K(1, 1) << " " << K(1, 2) << "; " << K(2, 0) << " " << K(2, 1)
        << " " << K(2, 2) << "]";
    throw InputError(msg.str());
  }
  Intrinsics intrinsics(K(0, 0), K(1, 1), K(0, 2), K(1, 2));
  intrinsics.validate();
  return intrinsics;
}

cv::Matx33d Intrinsics::matrix() const { return {fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0}; }

void Intrinsics::validate() const {
  if (!(std::isfinite(fx) && fx > 0.0 && std::isfinite(fy) && fy > 0.0)) {
    std::ostringstream msg;
    msg << "intrinsics: focal lengths must be finite and positive (fx = " << fx << ", fy = " << fy << ")";
    throw InputError(msg.str());
  }
  if (!(fx >= kMinFocal && fx <= kMaxFocal && fy >= kMinFocal && fy <= kMaxFocal)) {
    std::ostringstream msg;
    msg << "intrinsics: focal lengths must lie in [" << kMinFocal << ", " << kMaxFocal << "] pixels (fx = " << fx
        << ", fy = " << fy << ")";
    throw InputError(msg.str());
  }
  if (!(std::isfinite(cx) && std::isfinite(cy))) {
    throw InputError("intrinsics: principal point is not finite");
  }
}

void Intrinsics::validate(cv::Size image_size) const {
  validate();
  // Fields of view between about 1 and 175 degrees across the larger side.
  const double side = std::max(image_size.width, image_size.height);
  const double lo = kMinFocalPerSide * side, hi = kMaxFocalPerSide * side;
  if (fx < lo || fx > hi || fy < lo || fy > hi) {
    std::ostringstream msg;
    msg << "intrinsics: focal lengths (fx = " << fx << ", fy = " << fy << ") are not those of a camera with a "
        << image_size.width << "x" << image_size.height << " image: expected " << lo << " to " << hi << " pixels";
    throw InputError(msg.str());
  }
  if (cx < 0.0 || cy < 0.0 || cx > image_size.width || cy > image_size.height) {
    std::ostringstream msg;
    msg << "intrinsics: principal point (" << cx << ", " << cy << ") lies outside the "
        << image_size.width << "x" << image_size.height << " image";
    throw InputError(msg.str());
  }
}

}  // namespace risas

#include "risas/intrinsics.hpp"

#include "risas/errors.hpp"

#include <cmath>
#include <sstream>

namespace risas {

Intrinsics Intrinsics::fromMatrix(const cv::Matx33d& K) {
  const bool pinhole = K(0, 1) == 0.0 && K(1, 0) == 0.0 && K(2, 0) == 0.0 && K(2, 1) == 0.0 &&
                       K(2, 2) == 1.0;
  if (!pinhole) {
    std::ostringstream msg;
    msg << "camera matrix is not a pinhole K [fx 0 cx; 0 fy cy; 0 0 1]: " << K;
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
  if (!(std::isfinite(cx) && std::isfinite(cy))) {
    throw InputError("intrinsics: principal point is not finite");
  }
}

void Intrinsics::validate(cv::Size image_size) const {
  validate();
  if (cx < 0.0 || cy < 0.0 || cx > image_size.width || cy > image_size.height) {
    std::ostringstream msg;
    msg << "intrinsics: principal point (" << cx << ", " << cy << ") lies outside the "
        << image_size.width << "x" << image_size.height << " image";
    throw InputError(msg.str());
  }
}

}  // namespace risas

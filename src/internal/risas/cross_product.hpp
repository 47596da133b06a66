// [v]x, the cross-product matrix: crossProductMatrix(v) * w == v.cross(w).
// The Jacobian of a point under a small rotation of its frame.
#pragma once

#include <Eigen/Core>

namespace risas {

inline Eigen::Matrix3d crossProductMatrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

}  // namespace risas

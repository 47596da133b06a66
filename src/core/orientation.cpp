#include "risas/orientation.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <cmath>

namespace risas {
namespace {

// Image direction of a 3D direction d at point p: the Jacobian of the
// pinhole projection applied to d.
Eigen::Vector2d projectDirection(const Eigen::Vector3d& d, const Eigen::Vector3d& p, const Intrinsics& K) {
  const double z = p.z();
  return {K.fx * (d.x() * z - p.x() * d.z()) / (z * z), K.fy * (d.y() * z - p.y() * d.z()) / (z * z)};
}

double angleOf(const Eigen::Vector2d& d) { return std::atan2(d.y(), d.x()); }

}  // namespace

Orientation dominantOrientation(const Neighbourhood& nb, const Intrinsics& intrinsics, const DescriptorParams& params) {
  const double gamma = params.gamma;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(nb.covariance);  // ascending
  const Eigen::Vector3d e = solver.eigenvalues();
  const double e1 = e(2), e2 = e(1), e3 = e(0);
  const Eigen::Vector3d v1 = solver.eigenvectors().col(2);
  const Eigen::Vector3d v2 = solver.eigenvectors().col(1);

  Orientation result;
  Eigen::Vector3d d3d;
  if (e2 > gamma * e1 && e3 > gamma * e1) {
    return result;  // rejected
  } else if (e2 > gamma * e1) {
    result.source = OrientationSource::PatchNormal;
    d3d = v1.cross(v2).normalized();
    if (d3d.dot(nb.point) > 0.0) d3d = -d3d;  // face the camera
  } else {
    result.source = OrientationSource::MajorAxis;
    d3d = v1;
  }

  const Eigen::Vector2d& centroid = nb.intensity_centroid;
  const double sin_to_ray = d3d.cross(nb.point.normalized()).norm();
  if (!params.shape_orientation || sin_to_ray < std::sin(params.min_projection_angle_deg * CV_PI / 180.0)) {
    result.source = OrientationSource::IntensityCentroid;
    result.theta = angleOf(centroid);  // atan2(0, 0) = 0 for a flat patch
    return result;
  }
  Eigen::Vector2d d2d = projectDirection(d3d, nb.point, intrinsics);
  if (result.source == OrientationSource::MajorAxis && d2d.dot(centroid) < 0.0) d2d = -d2d;
  result.theta = angleOf(d2d);
  return result;
}

}  // namespace risas

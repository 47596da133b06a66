#include "risas/twist.hpp"

#include "risas/cross_product.hpp"
#include "risas/errors.hpp"
#include "risas/odometry.hpp"

#include <cmath>
#include <string>

namespace risas {
namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6>;

// log(T) = (v, w) with exp([w]x) = R and V(w) v = t, V = I + (1 - cos a) /
// a^2 W + (a - sin a) / a^3 W^2; its inverse in closed form (a = |w|).
Eigen::Matrix<double, 6, 1> logarithm(const Eigen::Isometry3d& T) {
  const Eigen::AngleAxisd rotation(T.linear());
  const double a = rotation.angle();
  const Eigen::Vector3d w = a * rotation.axis();
  const Eigen::Matrix3d W = crossProductMatrix(w);
  Eigen::Matrix3d V_inverse = Eigen::Matrix3d::Identity() - 0.5 * W;
  if (a > 1e-6) V_inverse += (1.0 - a * std::sin(a) / (2.0 * (1.0 - std::cos(a)))) / (a * a) * W * W;
  Eigen::Matrix<double, 6, 1> log;
  log << V_inverse * T.translation(), w;
  return log;
}

// The Jacobian of logarithm(T exp(d)) in d = (dp, dphi), the perturbation
// in T's own axes (T (dp, exp(dphi))), by central differences: exact to
// first order at any motion, where taking it as the identity would blur
// the axes by half the motion's rotation.
Matrix6 logarithmJacobian(const Eigen::Isometry3d& T) {
  constexpr double h = 1e-6;
  Matrix6 J;
  for (int k = 0; k < 6; ++k) {
    Eigen::Isometry3d plus = Eigen::Isometry3d::Identity(), minus = Eigen::Isometry3d::Identity();
    if (k < 3) {
      plus.translation()(k) = h;
      minus.translation()(k) = -h;
    } else {
      plus.linear() = Eigen::AngleAxisd(h, Eigen::Vector3d::Unit(k - 3)).toRotationMatrix();
      minus.linear() = Eigen::AngleAxisd(-h, Eigen::Vector3d::Unit(k - 3)).toRotationMatrix();
    }
    J.col(k) = (logarithm(T * plus) - logarithm(T * minus)) / (2.0 * h);
  }
  return J;
}

Matrix6 adjoint(const Eigen::Isometry3d& T) {
  Matrix6 Ad = Matrix6::Zero();
  Ad.topLeftCorner<3, 3>() = T.linear();
  Ad.topRightCorner<3, 3>() = crossProductMatrix(T.translation()) * T.linear();
  Ad.bottomRightCorner<3, 3>() = T.linear();
  return Ad;
}

}  // namespace

Twist twistFromMotion(const Eigen::Isometry3d& previous_T_current, const Matrix6& covariance, double dt) {
  if (!isTwistInterval(dt)) {
    throw InputError("twist: the time between the frames must be finite and at least 1 ns, got " +
                     std::to_string(dt) + " s");
  }
  Twist twist;
  twist.velocity = logarithm(previous_T_current) / dt;
  // (t + dt, exp(dtheta) R) = (R, t) (R^T dt, exp(R^T dtheta)): the
  // perturbation in the current frame's own axes, then through the
  // logarithm.
  const Matrix6 own_axes = rotateCovariance(covariance, previous_T_current.linear().transpose());
  const Matrix6 J = logarithmJacobian(previous_T_current);
  twist.covariance = J * own_axes * J.transpose() / (dt * dt);
  return twist;
}

Twist transformTwist(const Twist& twist_a, const Eigen::Isometry3d& b_T_a) {
  const Matrix6 Ad = adjoint(b_T_a);
  Twist twist_b;
  twist_b.velocity = Ad * twist_a.velocity;
  twist_b.covariance = Ad * twist_a.covariance * Ad.transpose();
  return twist_b;
}

}  // namespace risas

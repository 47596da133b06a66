// A frame's velocity from the odometry's frame-to-frame motion, as
// nav_msgs/Odometry's twist carries it: in the moving frame's own axes
// (child_frame_id), linear (m/s) then angular (rad/s), with its covariance
// in that order.
//
//   const risas::OdometryResult r = odometry.track(features);
//   if (r.motion_tracked) {
//     const risas::Twist camera = risas::twistFromMotion(r.previous_T_camera, r.motion_covariance, dt);
//     const risas::Twist base = risas::transformTwist(camera, base_T_camera);
//   }
#pragma once

#include <Eigen/Geometry>

#include <cmath>

namespace risas {

constexpr double kShortestTwistInterval = 1e-9;  // seconds

// Whether dt seconds is a time between two frames a twist can be taken
// over: finite and at least kShortestTwistInterval.
inline bool isTwistInterval(double dt) { return dt >= kShortestTwistInterval && std::isfinite(dt); }

struct Twist {
  Eigen::Matrix<double, 6, 1> velocity = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
};

// The constant twist that carries the previous frame onto the current one in
// dt seconds: the SE(3) logarithm of previous_T_current over dt (exact for a
// motion of constant velocity, whose body axes turn with it, so that the
// velocity is the same in the previous and the current frame's axes). The
// covariance: previous_T_current's (in the previous frame's axes, as
// odometry.hpp has it) carried through the logarithm to first order and
// divided by dt^2. InputError unless dt is finite and at least
// kShortestTwistInterval (a ROS stamp's resolution: shorter ones are no
// time between two frames, and would overflow the velocity).
Twist twistFromMotion(const Eigen::Isometry3d& previous_T_current, const Eigen::Matrix<double, 6, 6>& covariance,
                      double dt);

// The twist of a frame b rigidly attached to frame a (b_T_a fixed, as
// base_T_camera): the adjoint of b_T_a = (R, t), [[R, [t]x R], [0, R]], on
// the velocity and on both sides of the covariance. v_b = R v_a + t x w_b.
Twist transformTwist(const Twist& twist_a, const Eigen::Isometry3d& b_T_a);

}  // namespace risas

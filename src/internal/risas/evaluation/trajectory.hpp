// Trajectories as the TUM RGB-D benchmark scores them (Sturm et al., IROS
// 2012; its evaluate_ate.py and evaluate_rpe.py): files of
// "timestamp tx ty tz qx qy qz qw", the absolute trajectory error after a
// least-squares rigid alignment, and the relative pose error per pair of
// frames a fixed number of frames apart.
#pragma once

#include "risas/tum_sequence.hpp"

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace risas::eval {

using risas::StampedPose;  // files: risas::readTumTrajectory, writeTumTrajectory

// Estimate and ground-truth poses at the same moments: each estimate stamp
// with the nearest ground-truth stamp within max_difference seconds
// (associate.py's rule), in the estimate's order.
struct AssociatedTrajectory {
  std::vector<StampedPose> estimate, truth;
  std::vector<size_t> estimate_index;  // of each pair's pose in the estimate given
};
AssociatedTrajectory associate(const std::vector<StampedPose>& estimate, const std::vector<StampedPose>& truth,
                               double max_difference = kTumMaxDifference);

struct TrajectoryError {
  int poses = 0;                   // associated poses
  double ate_rmse = 0.0;           // m, after alignment
  double ate_mean = 0.0, ate_median = 0.0, ate_max = 0.0;
  int rpe_pairs = 0;
  double rpe_translation_rmse = 0.0;  // m per `delta` frames
  double rpe_rotation_rmse_deg = 0.0;
  Eigen::Isometry3d truth_T_estimate = Eigen::Isometry3d::Identity();  // the alignment
};

// ATE: the rigid motion (Horn/Umeyama, no scale) that best maps the
// estimate's positions onto the truth's, then the RMSE (and mean, median,
// max) of the remaining position differences. RPE: for each i, the
// relative motion E_i = (Q_i^-1 Q_{i+delta})^-1 (P_i^-1 P_{i+delta}) of
// truth Q and estimate P; the RMSE of its translation and of its rotation
// angle. InputError with fewer than 3 associated poses.
TrajectoryError trajectoryError(const AssociatedTrajectory& trajectory, int delta = 1);

// A reported pose covariance (odometry.hpp's convention, one per estimate
// pose) against the drift it stands for. Both trajectories are taken from
// their first pose, without an alignment (an odometry's world is its first
// camera): e_i the estimate's position minus the truth's, a_i the angle of
// the rotation between them, each against the trace of the covariance's
// position (rotation) block. Consistent: the ratios near 1, and |e| < 2σ on
// most poses (σ² the trace); above 1 the covariance is overconfident.
struct CovarianceConsistency {
  int poses = 0;                  // after the first
  double position_ratio = 0.0;    // mean |e|² / mean σ²
  double within_two_sigma = 0.0;  // share of poses with |e| < 2σ
  double rotation_ratio = 0.0;    // mean a² / mean σ_rotation², radians
};
// InputError unless there is one covariance per estimate pose and at least
// 2 poses.
CovarianceConsistency covarianceConsistency(const AssociatedTrajectory& trajectory,
                                            const std::vector<Eigen::Matrix<double, 6, 6>>& covariances);

// The frame-to-frame motions' covariances (OdometryResult::previous_T_camera
// and motion_covariance, what a twist is made of) against the truth's
// motion between the same two frames, measured as above with the motion
// in place of the drift. from and to index the estimate poses given to
// associate(); motions whose frames have no ground truth are left out.
struct FrameMotion {
  size_t from = 0, to = 0;
  Eigen::Isometry3d from_T_to = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();  // in from's axes
};
// poses is 0 (and so are the ratios) when no motion has ground truth at
// both ends.
CovarianceConsistency motionConsistency(const AssociatedTrajectory& trajectory, const std::vector<FrameMotion>& motions);

}  // namespace risas::eval

#include "risas/evaluation/trajectory.hpp"

#include "risas/errors.hpp"
#include "risas/tum_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace risas::eval {

AssociatedTrajectory associate(const std::vector<StampedPose>& estimate, const std::vector<StampedPose>& truth,
                               double max_difference) {
  std::vector<double> a, b;
  for (const StampedPose& p : estimate) a.push_back(p.stamp);
  for (const StampedPose& p : truth) b.push_back(p.stamp);
  AssociatedTrajectory t;
  for (const auto& [i, j] : associateStamps(a, b, max_difference)) {
    t.estimate.push_back(estimate[i]);
    t.truth.push_back(truth[j]);
    t.estimate_index.push_back(i);
  }
  return t;
}

TrajectoryError trajectoryError(const AssociatedTrajectory& trajectory, int delta) {
  const size_t n = trajectory.estimate.size();
  if (n < 3 || trajectory.truth.size() != n) {
    throw InputError("trajectory error needs at least 3 poses with ground truth, got " + std::to_string(n));
  }
  if (delta < 1) throw InputError("the RPE's delta must be at least one frame");
  TrajectoryError e;
  e.poses = static_cast<int>(n);
  Eigen::Matrix3Xd est(3, static_cast<Eigen::Index>(n)), gt(3, static_cast<Eigen::Index>(n));
  for (size_t i = 0; i < n; ++i) {
    est.col(static_cast<Eigen::Index>(i)) = trajectory.estimate[i].world_T_camera.translation();
    gt.col(static_cast<Eigen::Index>(i)) = trajectory.truth[i].world_T_camera.translation();
  }
  e.truth_T_estimate.matrix() = Eigen::umeyama(est, gt, false);
  std::vector<double> d(n);
  double sq = 0.0;
  for (size_t i = 0; i < n; ++i) {
    d[i] = (e.truth_T_estimate * est.col(static_cast<Eigen::Index>(i)) - gt.col(static_cast<Eigen::Index>(i))).norm();
    sq += d[i] * d[i];
    e.ate_mean += d[i] / static_cast<double>(n);
  }
  e.ate_rmse = std::sqrt(sq / static_cast<double>(n));
  e.ate_max = *std::max_element(d.begin(), d.end());
  std::sort(d.begin(), d.end());
  e.ate_median = n % 2 ? d[n / 2] : 0.5 * (d[n / 2 - 1] + d[n / 2]);

  double t_sq = 0.0, r_sq = 0.0;
  for (size_t i = 0; i + static_cast<size_t>(delta) < n; ++i) {
    const size_t j = i + static_cast<size_t>(delta);
    const Eigen::Isometry3d truth_motion =
        trajectory.truth[i].world_T_camera.inverse() * trajectory.truth[j].world_T_camera;
    const Eigen::Isometry3d estimated_motion =
        trajectory.estimate[i].world_T_camera.inverse() * trajectory.estimate[j].world_T_camera;
    const Eigen::Isometry3d error = truth_motion.inverse() * estimated_motion;
    t_sq += error.translation().squaredNorm();
    const double angle = Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI;
    r_sq += angle * angle;
    ++e.rpe_pairs;
  }
  if (e.rpe_pairs) {
    e.rpe_translation_rmse = std::sqrt(t_sq / e.rpe_pairs);
    e.rpe_rotation_rmse_deg = std::sqrt(r_sq / e.rpe_pairs);
  }
  return e;
}

CovarianceConsistency covarianceConsistency(const AssociatedTrajectory& trajectory,
                                            const std::vector<Eigen::Matrix<double, 6, 6>>& covariances) {
  const size_t n = trajectory.estimate.size();
  if (trajectory.truth.size() != n || covariances.size() != n) {
    throw InputError("covariance consistency needs one truth pose and one covariance per estimate pose");
  }
  if (n < 2) throw InputError("covariance consistency needs at least 2 poses, got " + std::to_string(n));
  const Eigen::Isometry3d estimate_origin = trajectory.estimate[0].world_T_camera.inverse();
  const Eigen::Isometry3d truth_origin = trajectory.truth[0].world_T_camera.inverse();
  double e_sq = 0.0, variance = 0.0, a_sq = 0.0, rotation_variance = 0.0;
  int within = 0;
  for (size_t i = 1; i < n; ++i) {
    const Eigen::Isometry3d estimate = estimate_origin * trajectory.estimate[i].world_T_camera;
    const Eigen::Isometry3d truth = truth_origin * trajectory.truth[i].world_T_camera;
    const double e2 = (estimate.translation() - truth.translation()).squaredNorm();
    const double s2 = covariances[i].topLeftCorner<3, 3>().trace();
    const double a = Eigen::AngleAxisd(estimate.linear() * truth.linear().transpose()).angle();
    e_sq += e2;
    variance += s2;
    a_sq += a * a;
    rotation_variance += covariances[i].bottomRightCorner<3, 3>().trace();
    within += e2 < 4.0 * s2;
  }
  CovarianceConsistency c;
  c.poses = static_cast<int>(n - 1);
  c.position_ratio = variance > 0.0 ? e_sq / variance : std::numeric_limits<double>::infinity();
  c.rotation_ratio = rotation_variance > 0.0 ? a_sq / rotation_variance : std::numeric_limits<double>::infinity();
  c.within_two_sigma = static_cast<double>(within) / c.poses;
  return c;
}

}  // namespace risas::eval

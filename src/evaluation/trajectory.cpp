#include "risas/evaluation/trajectory.hpp"

#include "risas/errors.hpp"
#include "risas/tum_sequence.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace risas::eval

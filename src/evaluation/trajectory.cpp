#include "risas/evaluation/trajectory.hpp"

#include "risas/errors.hpp"
#include "risas/evaluation/median.hpp"
#include "risas/tum_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

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
  e.ate_median = median(std::move(d));

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

namespace {

// Errors of estimated poses against the truth, each with the covariance it
// was reported with, tallied into CovarianceConsistency's ratios.
class ConsistencyTally {
 public:
  void add(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth, const Eigen::Matrix<double, 6, 6>& covariance) {
    const double e2 = (estimate.translation() - truth.translation()).squaredNorm();
    const double s2 = covariance.topLeftCorner<3, 3>().trace();
    const double a = Eigen::AngleAxisd(estimate.linear() * truth.linear().transpose()).angle();
    e_sq_ += e2;
    variance_ += s2;
    a_sq_ += a * a;
    rotation_variance_ += covariance.bottomRightCorner<3, 3>().trace();
    within_ += e2 < 4.0 * s2;
    ++poses_;
  }
  int poses() const { return poses_; }
  CovarianceConsistency result() const {
    CovarianceConsistency c;
    c.poses = poses_;
    c.position_ratio = variance_ > 0.0 ? e_sq_ / variance_ : std::numeric_limits<double>::infinity();
    c.rotation_ratio =
        rotation_variance_ > 0.0 ? a_sq_ / rotation_variance_ : std::numeric_limits<double>::infinity();
    c.within_two_sigma = static_cast<double>(within_) / poses_;
    return c;
  }

 private:
  double e_sq_ = 0.0, variance_ = 0.0, a_sq_ = 0.0, rotation_variance_ = 0.0;
  int within_ = 0, poses_ = 0;
};

}  // namespace

CovarianceConsistency covarianceConsistency(const AssociatedTrajectory& trajectory,
                                            const std::vector<Eigen::Matrix<double, 6, 6>>& covariances) {
  const size_t n = trajectory.estimate.size();
  if (trajectory.truth.size() != n || covariances.size() != n) {
    throw InputError("covariance consistency needs one truth pose and one covariance per estimate pose");
  }
  if (n < 2) throw InputError("covariance consistency needs at least 2 poses, got " + std::to_string(n));
  const Eigen::Isometry3d estimate_origin = trajectory.estimate[0].world_T_camera.inverse();
  const Eigen::Isometry3d truth_origin = trajectory.truth[0].world_T_camera.inverse();
  ConsistencyTally tally;
  for (size_t i = 1; i < n; ++i) {
    tally.add(estimate_origin * trajectory.estimate[i].world_T_camera,
              truth_origin * trajectory.truth[i].world_T_camera, covariances[i]);
  }
  return tally.result();
}

CovarianceConsistency motionConsistency(const AssociatedTrajectory& trajectory, const std::vector<FrameMotion>& motions) {
  // The truth at each estimate index that has one.
  std::vector<const Eigen::Isometry3d*> truth_at;
  for (size_t k = 0; k < trajectory.estimate_index.size(); ++k) {
    const size_t i = trajectory.estimate_index[k];
    if (truth_at.size() <= i) truth_at.resize(i + 1, nullptr);
    truth_at[i] = &trajectory.truth[k].world_T_camera;
  }
  const auto truth = [&](size_t i) { return i < truth_at.size() ? truth_at[i] : nullptr; };
  ConsistencyTally tally;
  for (const FrameMotion& m : motions) {
    const Eigen::Isometry3d *from = truth(m.from), *to = truth(m.to);
    if (from && to) tally.add(m.from_T_to, from->inverse() * *to, m.covariance);
  }
  return tally.poses() > 0 ? tally.result() : CovarianceConsistency();
}

}  // namespace risas::eval

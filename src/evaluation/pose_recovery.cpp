#include "risas/evaluation/pose_recovery.hpp"

#include "risas/evaluation/median.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <utility>

namespace risas::eval {

PoseError poseError(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth,
                    const std::vector<cv::Point3f>& points) {
  const Eigen::AngleAxisd difference(truth.linear().transpose() * estimate.linear());
  PoseError e{difference.angle() * 180.0 / M_PI, INFINITY};
  std::vector<double> distances;
  distances.reserve(points.size());
  for (const cv::Point3f& p : points) {
    const Eigen::Vector3d v(p.x, p.y, p.z);
    distances.push_back((estimate * v - truth * v).norm());
  }
  if (!distances.empty()) e.alignment_m = median(std::move(distances));
  return e;
}

namespace {

// visit(q, landing) for every `step`-th query pixel with depth, q its
// back-projected point, that ref_T_query moves inside the reference image in
// front of the camera (landInReference).
template <class Visit>
void forEachLanding(const cv::Mat& query_depth, const cv::Mat& reference_depth, const Intrinsics& K,
                    const Eigen::Isometry3d& ref_T_query, int step, Visit&& visit) {
  CV_Assert(query_depth.type() == CV_32FC1 && reference_depth.type() == CV_32FC1 && step > 0);
  for (int v = 0; v < query_depth.rows; v += step) {
    const float* depth = query_depth.ptr<float>(v);
    for (int u = 0; u < query_depth.cols; u += step) {
      if (!(depth[u] > 0.0f)) continue;  // NaN: no depth
      const cv::Point3f q = K.backProject(static_cast<float>(u), static_cast<float>(v), depth[u]);
      const auto landing = landInReference(Eigen::Vector3d(q.x, q.y, q.z), ref_T_query, K, reference_depth);
      if (landing) visit(q, *landing);
    }
  }
}

}  // namespace

std::vector<cv::Point3f> sharedScene(const cv::Mat& query_depth, const cv::Mat& reference_depth, const Intrinsics& K,
                                     const Eigen::Isometry3d& ref_T_query, int step) {
  std::vector<cv::Point3f> scene;
  forEachLanding(query_depth, reference_depth, K, ref_T_query, step,
                 [&](const cv::Point3f& q, const Landing&) { scene.push_back(q); });
  return scene;
}

double inlierSpread(const std::vector<cv::Point3f>& points) {
  if (points.size() < 2) return 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const cv::Point3f& p : points) mean += Eigen::Vector3d(p.x, p.y, p.z);
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const cv::Point3f& p : points) {
    const Eigen::Vector3d d = Eigen::Vector3d(p.x, p.y, p.z) - mean;
    covariance += d * d.transpose();
  }
  covariance /= static_cast<double>(points.size());
  // Eigenvalues in increasing order: the middle one.
  const Eigen::Vector3d variances = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly).eigenvalues();
  return std::sqrt(std::max(0.0, variances(1)));
}

double depthAgreement(const cv::Mat& query_depth, const cv::Mat& reference_depth, const Intrinsics& K,
                      const Eigen::Isometry3d& ref_T_query, double tolerance, int step) {
  long landed = 0, agreeing = 0;
  forEachLanding(query_depth, reference_depth, K, ref_T_query, step, [&](const cv::Point3f&, const Landing& landing) {
    if (!(landing.depth_there > 0.0f)) return;
    ++landed;
    if (std::abs(landing.depth_there - landing.depth) <= tolerance) ++agreeing;
  });
  return landed > 0 ? static_cast<double>(agreeing) / static_cast<double>(landed) : NAN;
}

MotionParams poseRecoveryRansac(int seed_index) {
  CV_Assert(seed_index >= 0);
  MotionParams p;
  p.inlier_threshold = 0.03;
  p.seed = 0x5eed + static_cast<unsigned int>(seed_index);
  return p;
}

PoseRecovery recoverPose(const std::vector<Candidate>& candidates, double ratio,
                         const std::vector<cv::Point3f>& query_points,
                         const std::vector<cv::Point3f>& reference_points, const Eigen::Isometry3d& ref_T_query,
                         const std::vector<cv::Point3f>& judged_points, const MotionParams& ransac, PoseRefit refit) {
  std::vector<cv::DMatch> matches;
  for (const Candidate& c : candidates) {
    if (c.ratio <= ratio && c.query >= 0 && c.reference >= 0) matches.emplace_back(c.query, c.reference, 0.0f);
  }
  PoseRecovery r;
  r.matches = static_cast<int>(matches.size());
  MotionEstimate m = estimateRigidMotion(query_points, reference_points, matches, ransac);
  if (refit == PoseRefit::Reprojection && m.valid) {
    m = refineByReprojection(query_points, reference_points, matches, m, OdometryParams().reprojection_huber);
  }
  r.estimated = m.valid;
  if (!m.valid) return r;
  r.inliers = m.num_inliers;
  r.estimate = m.train_T_query;
  std::vector<cv::Point3f> inlier_points;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (m.inliers[i]) inlier_points.push_back(query_points[static_cast<size_t>(matches[i].queryIdx)]);
  }
  r.inlier_spread_m = inlierSpread(inlier_points);
  r.error = poseError(m.train_T_query, ref_T_query, judged_points);
  return r;
}

std::vector<PoseRecovery> recoverPoseOverSeeds(const std::vector<Candidate>& candidates, double ratio,
                                               const std::vector<cv::Point3f>& query_points,
                                               const std::vector<cv::Point3f>& reference_points,
                                               const Eigen::Isometry3d& ref_T_query,
                                               const std::vector<cv::Point3f>& judged_points, int seeds, PoseRefit refit) {
  CV_Assert(seeds >= 1);
  std::vector<PoseRecovery> poses;
  for (int k = 0; k < seeds; ++k) {
    poses.push_back(recoverPose(candidates, ratio, query_points, reference_points, ref_T_query, judged_points,
                                poseRecoveryRansac(k), refit));
  }
  return poses;
}

}  // namespace risas::eval

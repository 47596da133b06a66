#include "risas/motion.hpp"

#include "risas/errors.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>

namespace risas {
namespace {

using Points = Eigen::Matrix<double, 3, Eigen::Dynamic>;

Eigen::Isometry3d solveUmeyama(const Points& src, const Points& dst) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.matrix() = Eigen::umeyama(src, dst, false);
  return T;
}

// Three points spanning too small a triangle fix no rotation.
bool degenerate(const Points& p) {
  const Eigen::Vector3d a = p.col(1) - p.col(0), b = p.col(2) - p.col(0);
  return a.cross(b).norm() < 1e-4;  // twice the area, m^2: a 1 cm x 1 cm triangle
}

int countInliers(const Eigen::Isometry3d& T, const Points& src, const Points& dst, double threshold,
                 std::vector<char>* inliers, double* sum_sq) {
  int count = 0;
  double sq = 0.0;
  for (Eigen::Index i = 0; i < src.cols(); ++i) {
    const double e = (T * src.col(i) - dst.col(i)).squaredNorm();
    const bool in = e <= threshold * threshold;
    if (inliers) (*inliers)[static_cast<size_t>(i)] = in;
    if (in) {
      ++count;
      sq += e;
    }
  }
  if (sum_sq) *sum_sq = sq;
  return count;
}

}  // namespace

MotionEstimate estimateRigidMotion(const std::vector<cv::Point3f>& query_points,
                                   const std::vector<cv::Point3f>& train_points,
                                   const std::vector<cv::DMatch>& matches, const MotionParams& params) {
  params.validate();
  const Eigen::Index n = static_cast<Eigen::Index>(matches.size());
  Points src(3, n), dst(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const cv::DMatch& m = matches[static_cast<size_t>(i)];
    if (m.queryIdx < 0 || m.trainIdx < 0 || m.queryIdx >= static_cast<int>(query_points.size()) ||
        m.trainIdx >= static_cast<int>(train_points.size())) {
      throw InputError("match " + std::to_string(i) + " indexes a point that does not exist");
    }
    const cv::Point3f& q = query_points[static_cast<size_t>(m.queryIdx)];
    const cv::Point3f& t = train_points[static_cast<size_t>(m.trainIdx)];
    src.col(i) = Eigen::Vector3d(q.x, q.y, q.z);
    dst.col(i) = Eigen::Vector3d(t.x, t.y, t.z);
  }

  MotionEstimate result;
  result.inliers.assign(static_cast<size_t>(n), 0);
  if (n < std::max(3, params.min_inliers)) return result;

  std::mt19937 rng(params.seed);
  std::uniform_int_distribution<Eigen::Index> pick(0, n - 1);
  int best = 0;
  Eigen::Isometry3d best_T = Eigen::Isometry3d::Identity();
  long iterations = params.max_iterations;
  for (long it = 0; it < iterations; ++it) {
    Eigen::Index idx[3] = {pick(rng), pick(rng), pick(rng)};
    if (idx[0] == idx[1] || idx[0] == idx[2] || idx[1] == idx[2]) continue;
    Points s(3, 3), d(3, 3);
    for (int k = 0; k < 3; ++k) {
      s.col(k) = src.col(idx[k]);
      d.col(k) = dst.col(idx[k]);
    }
    if (degenerate(s) || degenerate(d)) continue;
    const Eigen::Isometry3d T = solveUmeyama(s, d);
    const int count = countInliers(T, src, dst, params.inlier_threshold, nullptr, nullptr);
    if (count > best) {
      best = count;
      best_T = T;
      // Adaptive stop: enough samples for an all-inlier draw at `confidence`
      // (a confidence of 1 never stops early; the bound is taken in double,
      // before the conversion, so that it stays in a long's range).
      const double w = static_cast<double>(best) / n;
      const double p_fail = 1.0 - w * w * w;
      if (p_fail <= 1e-12) break;
      if (params.confidence < 1.0) {
        const double needed = std::log(1.0 - params.confidence) / std::log(p_fail);
        iterations = static_cast<long>(std::min<double>(params.max_iterations, std::ceil(needed)));
      }
    }
  }
  if (best < params.min_inliers) return result;

  // Refit on all inliers until the set stops changing.
  Eigen::Isometry3d T = best_T;
  std::vector<char> inliers(static_cast<size_t>(n), 0);
  double sum_sq = 0.0;
  int count = countInliers(T, src, dst, params.inlier_threshold, &inliers, &sum_sq);
  for (int round = 0; round < 5; ++round) {
    Points s(3, count), d(3, count);
    for (Eigen::Index i = 0, j = 0; i < n; ++i) {
      if (!inliers[static_cast<size_t>(i)]) continue;
      s.col(j) = src.col(i);
      d.col(j) = dst.col(i);
      ++j;
    }
    const Eigen::Isometry3d refined = solveUmeyama(s, d);
    std::vector<char> refined_inliers(static_cast<size_t>(n), 0);
    double refined_sq = 0.0;
    const int refined_count = countInliers(refined, src, dst, params.inlier_threshold, &refined_inliers, &refined_sq);
    if (refined_count < count) break;
    const bool same = refined_inliers == inliers;
    T = refined;
    inliers.swap(refined_inliers);
    count = refined_count;
    sum_sq = refined_sq;
    if (same) break;
  }
  result.valid = count >= params.min_inliers;
  result.train_T_query = T;
  result.inliers = inliers;
  result.num_inliers = count;
  result.rmse = std::sqrt(sum_sq / std::max(count, 1));
  return result;
}

}  // namespace risas

#include "risas/motion.hpp"

#include "risas/cross_product.hpp"
#include "risas/errors.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>

namespace risas {
namespace {

using Points = Eigen::Matrix<double, 3, Eigen::Dynamic>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// The points match i pairs, as (query, train); InputError on an index out
// of range.
std::pair<Eigen::Vector3d, Eigen::Vector3d> matchedPoints(const std::vector<cv::Point3f>& query_points,
                                                          const std::vector<cv::Point3f>& train_points,
                                                          const std::vector<cv::DMatch>& matches, size_t i) {
  const cv::DMatch& m = matches[i];
  if (m.queryIdx < 0 || m.trainIdx < 0 || m.queryIdx >= static_cast<int>(query_points.size()) ||
      m.trainIdx >= static_cast<int>(train_points.size())) {
    throw InputError("match " + std::to_string(i) + " indexes a point that does not exist");
  }
  const cv::Point3f& q = query_points[static_cast<size_t>(m.queryIdx)];
  const cv::Point3f& t = train_points[static_cast<size_t>(m.trainIdx)];
  return {Eigen::Vector3d(q.x, q.y, q.z), Eigen::Vector3d(t.x, t.y, t.z)};
}

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

// The matches within threshold of T's prediction; their flags and sum of
// squared errors when asked. RANSAC runs this once per sample, so it is
// written in scalars: `(T * p - q).squaredNorm()` forms Eigen's 4x4
// homogeneous product through expression objects that the sanitized build
// does not inline (two thirds of risas_fit_intrinsics's time under ASan;
// docs/ci.md). Each term is the one Eigen forms, summed in the same order
// (row by row ((R0 x + R1 y) + R2 z) + t, its product with (x, y, z, 1)),
// so the result is the same to the bit, which test_matcher_motion.cpp
// holds.
int countInliers(const Eigen::Isometry3d& T, const Points& src, const Points& dst, double threshold,
                 std::vector<char>* inliers, double* sum_sq) {
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Vector3d t = T.translation();
  int count = 0;
  double sq = 0.0;
  for (Eigen::Index i = 0; i < src.cols(); ++i) {
    const double x = src(0, i), y = src(1, i), z = src(2, i);
    const double dx = R(0, 0) * x + R(0, 1) * y + R(0, 2) * z + t(0) - dst(0, i);
    const double dy = R(1, 0) * x + R(1, 1) * y + R(1, 2) * z + t(1) - dst(1, i);
    const double dz = R(2, 0) * x + R(2, 1) * y + R(2, 2) * z + t(2) - dst(2, i);
    const double e = dx * dx + dy * dy + dz * dz;
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

// A train point and the bearing (x/z, y/z) of its match in the query frame.
struct Observation {
  Eigen::Vector3d train_point;
  Eigen::Vector2d query_bearing;
};

// The Huber cost of the observations' reprojection errors under
// query_T_train, and (when H is given) its Gauss-Newton normal equations
// H d = -g for a small motion d = (translation, rotation) applied on the
// left. Infinite when a point falls behind the query camera.
double reprojectionCost(const std::vector<Observation>& observations, const Eigen::Isometry3d& query_T_train,
                        double huber, Matrix6* H, Vector6* g) {
  double cost = 0.0;
  if (H) {
    H->setZero();
    g->setZero();
  }
  for (const Observation& o : observations) {
    const Eigen::Vector3d X = query_T_train * o.train_point;
    if (!(X.z() > 1e-6)) return std::numeric_limits<double>::infinity();
    const Eigen::Vector2d r = X.head<2>() / X.z() - o.query_bearing;
    const double e = r.norm();
    cost += e <= huber ? 0.5 * e * e : huber * (e - 0.5 * huber);
    if (!H) continue;
    const double w = e <= huber ? 1.0 : huber / e;  // IRLS weight of the Huber loss
    Eigen::Matrix<double, 2, 3> projection;
    projection << 1.0, 0.0, -X.x() / X.z(), 0.0, 1.0, -X.y() / X.z();
    projection /= X.z();
    Eigen::Matrix<double, 3, 6> motion;
    motion.leftCols<3>() = Eigen::Matrix3d::Identity();
    motion.rightCols<3>() = -crossProductMatrix(X);
    const Eigen::Matrix<double, 2, 6> J = projection * motion;
    *H += w * J.transpose() * J;
    *g += w * J.transpose() * r;
  }
  return cost;
}

Eigen::Isometry3d smallMotion(const Vector6& d) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const double angle = d.tail<3>().norm();
  if (angle > 0.0) T.linear() = Eigen::AngleAxisd(angle, d.tail<3>() / angle).toRotationMatrix();
  T.translation() = d.head<3>();
  return T;
}

}  // namespace

MotionEstimate estimateRigidMotion(const std::vector<cv::Point3f>& query_points,
                                   const std::vector<cv::Point3f>& train_points,
                                   const std::vector<cv::DMatch>& matches, const MotionParams& params) {
  params.validate();
  const Eigen::Index n = static_cast<Eigen::Index>(matches.size());
  Points src(3, n), dst(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto [q, t] = matchedPoints(query_points, train_points, matches, static_cast<size_t>(i));
    src.col(i) = q;
    dst.col(i) = t;
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

MotionEstimate refineByReprojection(const std::vector<cv::Point3f>& query_points,
                                    const std::vector<cv::Point3f>& train_points,
                                    const std::vector<cv::DMatch>& matches, const MotionEstimate& estimate,
                                    double huber) {
  if (!(huber > 0.0) || !std::isfinite(huber)) {
    throw InputError("the reprojection refit's Huber width must be positive and finite, got " + std::to_string(huber));
  }
  if (!estimate.valid) return estimate;
  if (estimate.inliers.size() != matches.size()) {
    throw InputError("the estimate has " + std::to_string(estimate.inliers.size()) + " inlier flags for " +
                     std::to_string(matches.size()) + " matches");
  }
  std::vector<Observation> observations;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> inlier_pairs;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (!estimate.inliers[i]) continue;
    const auto [q, t] = matchedPoints(query_points, train_points, matches, i);
    inlier_pairs.emplace_back(q, t);
    if (q.z() > 0.0 && t.z() > 0.0) observations.push_back({t, q.head<2>() / q.z()});
  }
  if (observations.size() < 3) return estimate;

  Eigen::Isometry3d query_T_train = estimate.train_T_query.inverse();
  Matrix6 H;
  Vector6 g;
  double cost = reprojectionCost(observations, query_T_train, huber, &H, &g);
  const double initial_cost = cost;
  for (int iteration = 0; iteration < 20 && std::isfinite(cost); ++iteration) {
    const Vector6 d = -(H + 1e-12 * Matrix6::Identity()).ldlt().solve(g);
    if (!d.allFinite()) break;
    const Eigen::Isometry3d candidate = smallMotion(d) * query_T_train;
    const double candidate_cost = reprojectionCost(observations, candidate, huber, nullptr, nullptr);
    if (!(candidate_cost < cost)) break;  // converged, or a step that does not descend
    query_T_train = candidate;
    cost = reprojectionCost(observations, query_T_train, huber, &H, &g);
    if (d.norm() < 1e-10) break;
  }
  if (!(cost < initial_cost)) return estimate;

  MotionEstimate refined = estimate;
  refined.train_T_query = query_T_train.inverse();
  double sum_sq = 0.0;
  for (const auto& [q, t] : inlier_pairs) sum_sq += (refined.train_T_query * q - t).squaredNorm();
  refined.rmse = std::sqrt(sum_sq / static_cast<double>(inlier_pairs.size()));
  return refined;
}

}  // namespace risas

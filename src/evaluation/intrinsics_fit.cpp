#include "risas/evaluation/intrinsics_fit.hpp"

#include "risas/errors.hpp"
#include "risas/motion.hpp"

#include <algorithm>
#include <array>

namespace risas::eval {

namespace {

constexpr double kInlierMetres = 0.03;  // the evaluation's RANSAC inlier distance
constexpr double kScanPixels = 96.0, kScanStep = 8.0;  // the principal point's scan about the start

// Each match's residual under its pair's RANSAC motion, given `intrinsics`.
template <typename PerResidual>
void forEachResidual(const DepthMatches& pair, const Intrinsics& intrinsics, PerResidual&& per_residual) {
  const size_t n = pair.reference_pixels.size();
  if (pair.query_pixels.size() != n || pair.reference_depths.size() != n || pair.query_depths.size() != n) {
    throw InputError("the matches' pixels and depths differ in number");
  }
  std::vector<cv::Point3f> reference, query;
  std::vector<cv::DMatch> matches;
  for (size_t i = 0; i < n; ++i) {
    reference.push_back(intrinsics.backProject(pair.reference_pixels[i].x, pair.reference_pixels[i].y,
                                               pair.reference_depths[i]));
    query.push_back(intrinsics.backProject(pair.query_pixels[i].x, pair.query_pixels[i].y, pair.query_depths[i]));
    matches.emplace_back(static_cast<int>(i), static_cast<int>(i), 0.0f);
  }
  MotionParams params;
  params.inlier_threshold = kInlierMetres;
  const MotionEstimate motion = estimateRigidMotion(query, reference, matches, params);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d q(query[i].x, query[i].y, query[i].z), r(reference[i].x, reference[i].y, reference[i].z);
    per_residual(motion.valid ? (motion.train_T_query * q - r).norm() : kInlierMetres);
  }
}

}  // namespace

double rigidityCost(const std::vector<DepthMatches>& pairs, const Intrinsics& intrinsics) {
  double total = 0.0;
  for (const DepthMatches& pair : pairs) {
    double sum = 0.0;
    forEachResidual(pair, intrinsics, [&](double r) { sum += std::min(r * r, kInlierMetres * kInlierMetres); });
    if (!pair.reference_pixels.empty()) total += sum / static_cast<double>(pair.reference_pixels.size());
  }
  return pairs.empty() ? 0.0 : total / static_cast<double>(pairs.size());
}

int rigidMatches(const std::vector<DepthMatches>& pairs, const Intrinsics& intrinsics, double metres) {
  int count = 0;
  for (const DepthMatches& pair : pairs) {
    forEachResidual(pair, intrinsics, [&](double r) { count += r <= metres ? 1 : 0; });
  }
  return count;
}

IntrinsicsFit fitIntrinsics(const std::vector<DepthMatches>& pairs, const Intrinsics& start) {
  start.validate();
  const MotionParams motion;
  const bool any_fit = std::any_of(pairs.begin(), pairs.end(), [&](const DepthMatches& pair) {
    return pair.reference_pixels.size() >= static_cast<size_t>(motion.min_inliers);
  });
  if (!any_fit) {
    throw InputError("no pair has the " + std::to_string(motion.min_inliers) +
                     " matches with depth a rigid motion needs: nothing to fit the intrinsics to");
  }
  IntrinsicsFit fit{start, rigidityCost(pairs, start), 0.0};
  std::array<double, 4> k = {start.fx, start.fy, start.cx, start.cy};
  const auto intrinsicsOf = [](const std::array<double, 4>& p) { return Intrinsics(p[0], p[1], p[2], p[3]); };
  double best = fit.cost_before;
  // The principal point scanned first: the cost is jagged (RANSAC takes
  // other inliers as K moves), and a descent from a point 60 px off can
  // stop on a ridge before it.
  const std::array<double, 4> scan_centre = k;
  for (double dx = -kScanPixels; dx <= kScanPixels; dx += kScanStep) {
    for (double dy = -kScanPixels; dy <= kScanPixels; dy += kScanStep) {
      std::array<double, 4> trial = scan_centre;
      trial[2] += dx;
      trial[3] += dy;
      const double cost = rigidityCost(pairs, intrinsicsOf(trial));
      if (cost < best) {
        best = cost;
        k = trial;
      }
    }
  }
  std::array<double, 4> step = {16.0, 16.0, 16.0, 16.0};
  // Each accepted move lowers the cost; the bound only guards the loop.
  for (int sweep = 0; sweep < 1000 && step[0] >= 0.25; ++sweep) {
    bool moved = false;
    for (size_t j = 0; j < k.size(); ++j) {
      for (const double sign : {-1.0, 1.0}) {
        std::array<double, 4> trial = k;
        trial[j] += sign * step[j];
        if (trial[0] < Intrinsics::kMinFocal || trial[1] < Intrinsics::kMinFocal) continue;
        const double cost = rigidityCost(pairs, intrinsicsOf(trial));
        if (cost < best) {
          best = cost;
          k = trial;
          moved = true;
        }
      }
    }
    if (!moved) {
      for (double& s : step) s /= 2.0;
    }
  }
  fit.intrinsics = intrinsicsOf(k);
  fit.cost_after = best;
  return fit;
}

}  // namespace risas::eval

#include "risas/evaluation/metrics.hpp"

#include "risas/errors.hpp"

#include <opencv2/features2d.hpp>

#include <algorithm>
#include <cmath>

namespace risas::eval {

bool isCorrect(const cv::Point3f& reference, const cv::Point3f& query, const Eigen::Isometry3d& ref_T_query,
               double d_min) {
  const Eigen::Vector3d moved = ref_T_query * Eigen::Vector3d(query.x, query.y, query.z);
  return (Eigen::Vector3d(reference.x, reference.y, reference.z) - moved).norm() <= d_min;
}

std::vector<Candidate> nearestNeighbourCandidates(const cv::Mat& query, const cv::Mat& reference, int norm,
                                                  const std::vector<cv::Point3f>& query_points,
                                                  const std::vector<cv::Point3f>& reference_points,
                                                  const Eigen::Isometry3d& ref_T_query, double d_min) {
  if (query.rows != static_cast<int>(query_points.size()) || reference.rows != static_cast<int>(reference_points.size())) {
    throw InputError("descriptors and points differ in count");
  }
  std::vector<Candidate> candidates;
  if (query.empty() || reference.rows < 2) return candidates;
  std::vector<std::vector<cv::DMatch>> knn;
  cv::BFMatcher(norm).knnMatch(query, reference, knn, 2);
  for (const auto& pair : knn) {
    if (pair.size() < 2) continue;
    const double d1 = pair[0].distance, d2 = pair[1].distance;
    const double ratio = d2 > 0.0 ? d1 / d2 : 1.0;  // two identical neighbours: undecidable
    candidates.push_back({ratio,
                          isCorrect(reference_points[static_cast<size_t>(pair[0].trainIdx)],
                                    query_points[static_cast<size_t>(pair[0].queryIdx)], ref_T_query, d_min),
                          pair[0].queryIdx, pair[0].trainIdx});
  }
  return candidates;
}

std::optional<Landing> landInReference(const Eigen::Vector3d& query_point, const Eigen::Isometry3d& ref_T_query,
                                       const Intrinsics& K, const cv::Mat& reference_depth_metres) {
  const Eigen::Vector3d p = ref_T_query * query_point;
  if (!(p.z() > 0.0)) return std::nullopt;
  const double u = K.fx * p.x() / p.z() + K.cx, v = K.fy * p.y() / p.z() + K.cy;
  const long iu = std::lround(u), iv = std::lround(v);
  if (iu < 0 || iv < 0 || iu >= reference_depth_metres.cols || iv >= reference_depth_metres.rows) return std::nullopt;
  return Landing{u, v, p.z(), reference_depth_metres.at<float>(static_cast<int>(iv), static_cast<int>(iu))};
}

Repeatability detectorRepeatability(const std::vector<cv::Point3f>& query_points,
                                    const std::vector<cv::Point2f>& reference_pixels,
                                    const cv::Mat& reference_depth_metres, const Intrinsics& intrinsics,
                                    const Eigen::Isometry3d& ref_T_query, double pixel_tolerance,
                                    double depth_tolerance) {
  CV_Assert(reference_depth_metres.type() == CV_32FC1);
  Repeatability r;
  const double tol2 = pixel_tolerance * pixel_tolerance;
  struct Pairing {
    double distance2;
    size_t query, reference;
  };
  std::vector<Pairing> pairings;  // every visible query's reference keypoints within the tolerance
  for (size_t i = 0; i < query_points.size(); ++i) {
    const cv::Point3f& q = query_points[i];
    const auto landing = landInReference(Eigen::Vector3d(q.x, q.y, q.z), ref_T_query, intrinsics, reference_depth_metres);
    if (!landing || !(std::abs(landing->depth_there - landing->depth) <= depth_tolerance)) continue;  // occluded, or no depth there
    ++r.visible;
    for (size_t j = 0; j < reference_pixels.size(); ++j) {
      const double du = reference_pixels[j].x - landing->u, dv = reference_pixels[j].y - landing->v;
      if (du * du + dv * dv <= tol2) pairings.push_back({du * du + dv * dv, i, j});
    }
  }
  // One to one, nearest pairs first: a reference keypoint found again counts
  // once, so a dense cluster of reference keypoints does not collect the
  // projections of every query keypoint near it.
  std::stable_sort(pairings.begin(), pairings.end(),
                   [](const Pairing& a, const Pairing& b) { return a.distance2 < b.distance2; });
  std::vector<char> query_taken(query_points.size(), 0), reference_taken(reference_pixels.size(), 0);
  for (const Pairing& pairing : pairings) {
    if (query_taken[pairing.query] || reference_taken[pairing.reference]) continue;
    query_taken[pairing.query] = reference_taken[pairing.reference] = 1;
    ++r.repeated;
  }
  return r;
}

int countPositives(const std::vector<cv::Point3f>& query_points, const std::vector<cv::Point3f>& reference_points,
                   const Eigen::Isometry3d& ref_T_query, double d_min) {
  int positives = 0;
  for (const cv::Point3f& q : query_points) {
    positives += std::any_of(reference_points.begin(), reference_points.end(),
                             [&](const cv::Point3f& r) { return isCorrect(r, q, ref_T_query, d_min); });
  }
  return positives;
}

namespace {

// Whether p lies within sqrt(tol2) pixels of one of `kept`.
bool nearAny(const std::vector<cv::Point2f>& kept, const cv::Point2f& p, double tol2) {
  return std::any_of(kept.begin(), kept.end(), [&](const cv::Point2f& q) {
    const cv::Point2f d = p - q;
    return d.dot(d) <= tol2;
  });
}

}  // namespace

int distinctCorrectMatches(const std::vector<Candidate>& candidates, const std::vector<cv::Point2f>& query_pixels,
                           const std::vector<cv::Point2f>& reference_pixels, double threshold,
                           double pixel_tolerance) {
  std::vector<const Candidate*> passed;
  for (const Candidate& c : candidates) {
    if (c.correct && c.ratio <= threshold) passed.push_back(&c);
  }
  std::stable_sort(passed.begin(), passed.end(), [](const Candidate* a, const Candidate* b) { return a->ratio < b->ratio; });
  const double tol2 = pixel_tolerance * pixel_tolerance;
  std::vector<cv::Point2f> counted_query, counted_reference;
  for (const Candidate* c : passed) {
    const cv::Point2f& q = query_pixels.at(static_cast<size_t>(c->query));
    const cv::Point2f& r = reference_pixels.at(static_cast<size_t>(c->reference));
    if (nearAny(counted_query, q, tol2) || nearAny(counted_reference, r, tol2)) continue;
    counted_query.push_back(q);
    counted_reference.push_back(r);
  }
  return static_cast<int>(counted_query.size());
}

std::vector<cv::KeyPoint> onePerImagePoint(std::vector<cv::KeyPoint> keypoints, double pixel_tolerance) {
  std::stable_sort(keypoints.begin(), keypoints.end(),
                   [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  const double tol2 = pixel_tolerance * pixel_tolerance;
  std::vector<cv::KeyPoint> kept;
  std::vector<cv::Point2f> kept_pixels;
  for (const cv::KeyPoint& k : keypoints) {
    if (nearAny(kept_pixels, k.pt, tol2)) continue;
    kept.push_back(k);
    kept_pixels.push_back(k.pt);
  }
  return kept;
}

std::vector<PrPoint> prCurve(std::vector<Candidate> candidates, int positives) {
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) { return a.ratio < b.ratio; });
  std::vector<PrPoint> curve;
  int matches = 0, correct = 0;
  for (size_t i = 0; i < candidates.size(); ++i) {
    ++matches;
    correct += candidates[i].correct;
    // Equal ratios enter together: one threshold cannot split them.
    if (i + 1 < candidates.size() && candidates[i + 1].ratio == candidates[i].ratio) continue;
    curve.push_back({candidates[i].ratio, static_cast<double>(correct) / matches,
                     positives > 0 ? static_cast<double>(correct) / positives : 0.0, matches, correct});
  }
  return curve;
}

double prAuc(const std::vector<PrPoint>& curve) {
  double auc = 0.0, previous_recall = 0.0;
  for (const PrPoint& p : curve) {
    auc += (p.recall - previous_recall) * p.precision;
    previous_recall = p.recall;
  }
  return auc;
}

PrPoint atThreshold(const std::vector<PrPoint>& curve, double threshold) {
  PrPoint state{threshold, 0.0, 0.0, 0, 0};
  for (const PrPoint& p : curve) {
    if (p.ratio > threshold) break;
    state = p;
    state.ratio = threshold;
  }
  return state;
}

}  // namespace risas::eval

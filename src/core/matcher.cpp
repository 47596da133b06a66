#include "risas/matcher.hpp"

#include "risas/errors.hpp"

#include <opencv2/features2d.hpp>

namespace risas {
namespace {

// The norm of the descriptors' type: L2 for CV_32F (RISAS, SIFT), Hamming
// for CV_8U (binary: ORB, BRIEF).
int normOf(const cv::Mat& query, const cv::Mat& train) {
  const cv::Mat& any = query.empty() ? train : query;
  return any.type() == CV_8U ? cv::NORM_HAMMING : cv::NORM_L2;
}

void checkDescriptors(const cv::Mat& query, const cv::Mat& train) {
  const auto supported = [](const cv::Mat& m) { return m.empty() || m.type() == CV_32F || m.type() == CV_8U; };
  if (!supported(query) || !supported(train)) throw InputError("descriptors must be CV_32F (L2) or CV_8U (binary, Hamming)");
  if (!query.empty() && !train.empty() && query.type() != train.type()) {
    throw InputError("descriptors differ in type (" + cv::typeToString(query.type()) + " vs " +
                     cv::typeToString(train.type()) + ")");
  }
  if (!query.empty() && !train.empty() && query.cols != train.cols) {
    throw InputError("descriptors differ in width (" + std::to_string(query.cols) + " vs " +
                     std::to_string(train.cols) + "): they come from different parameters");
  }
}

}  // namespace

std::vector<std::vector<cv::DMatch>> nearestTwo(const cv::Mat& query, const cv::Mat& train) {
  checkDescriptors(query, train);
  std::vector<std::vector<cv::DMatch>> knn;
  if (query.empty() || train.empty()) {
    knn.resize(static_cast<size_t>(query.rows));
    return knn;
  }
  cv::BFMatcher(normOf(query, train)).knnMatch(query, train, knn, 2);
  return knn;
}

std::vector<cv::DMatch> matchDescriptors(const cv::Mat& query, const cv::Mat& train, const MatchParams& params) {
  params.validate();
  const auto knn = nearestTwo(query, train);
  std::vector<int> best_query_of_train;
  if (params.cross_check && !query.empty() && !train.empty()) {
    std::vector<cv::DMatch> back;
    cv::BFMatcher(normOf(query, train)).match(train, query, back);
    best_query_of_train.resize(static_cast<size_t>(train.rows), -1);
    for (const cv::DMatch& m : back) best_query_of_train[static_cast<size_t>(m.queryIdx)] = m.trainIdx;
  }
  std::vector<cv::DMatch> matches;
  for (const auto& candidates : knn) {
    if (candidates.empty()) continue;
    const cv::DMatch& best = candidates[0];
    if (candidates.size() > 1 && !(best.distance < params.ratio * candidates[1].distance)) continue;
    if (params.cross_check && best_query_of_train[static_cast<size_t>(best.trainIdx)] != best.queryIdx) continue;
    matches.push_back(best);
  }
  return matches;
}

}  // namespace risas

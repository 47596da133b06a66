#include "risas/overlay.hpp"

#include "risas/errors.hpp"

#include <opencv2/imgproc.hpp>

namespace risas {
namespace {

cv::Mat toBgr(const cv::Mat& image) {
  cv::Mat bgr;
  if (image.channels() == 1) {
    cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  } else {
    bgr = image;
  }
  return bgr;
}

}  // namespace

cv::Mat drawMatchOverlay(const cv::Mat& left, const std::vector<cv::KeyPoint>& left_keypoints,
                         const cv::Mat& right, const std::vector<cv::KeyPoint>& right_keypoints,
                         const std::vector<cv::DMatch>& matches, const std::vector<char>& inliers,
                         const std::string& caption) {
  if (left.empty() || right.empty() || left.depth() != CV_8U || right.depth() != CV_8U) {
    throw InputError("overlay needs two non-empty 8-bit images");
  }
  if (!inliers.empty() && inliers.size() != matches.size()) throw InputError("overlay: one inlier flag per match");
  const int band = 28;
  const cv::Size size(left.cols + right.cols, std::max(left.rows, right.rows) + band);
  cv::Mat canvas(size, CV_8UC3, cv::Scalar(0, 0, 0));
  toBgr(left).copyTo(canvas(cv::Rect(0, band, left.cols, left.rows)));
  toBgr(right).copyTo(canvas(cv::Rect(left.cols, band, right.cols, right.rows)));
  const cv::Point2f left_origin(0.0f, band), right_origin(static_cast<float>(left.cols), band);

  const cv::Scalar point_colour(255, 200, 0);
  for (const cv::KeyPoint& k : left_keypoints) cv::circle(canvas, k.pt + left_origin, 2, point_colour, 1, cv::LINE_AA);
  for (const cv::KeyPoint& k : right_keypoints) cv::circle(canvas, k.pt + right_origin, 2, point_colour, 1, cv::LINE_AA);
  for (size_t i = 0; i < matches.size(); ++i) {
    const cv::DMatch& m = matches[i];
    if (m.trainIdx < 0 || m.queryIdx < 0 || m.trainIdx >= static_cast<int>(left_keypoints.size()) ||
        m.queryIdx >= static_cast<int>(right_keypoints.size())) {
      throw InputError("overlay: a match indexes a keypoint that does not exist");
    }
    const cv::Scalar colour = inliers.empty() ? cv::Scalar(0, 220, 220)
                              : inliers[i]    ? cv::Scalar(0, 200, 0)
                                              : cv::Scalar(0, 0, 230);
    cv::line(canvas, left_keypoints[static_cast<size_t>(m.trainIdx)].pt + left_origin,
             right_keypoints[static_cast<size_t>(m.queryIdx)].pt + right_origin, colour, 1, cv::LINE_AA);
  }
  cv::putText(canvas, caption, cv::Point(8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
  return canvas;
}

}  // namespace risas

// The match overlay shown by risas_match and the ROS nodelet.
#pragma once

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace risas {

// Left and right images (grey or BGR) side by side, BGR 8-bit; every keypoint
// as a small circle, every match as a line from left keypoint trainIdx to
// right keypoint queryIdx: green when inliers[i] is set, red otherwise (all
// yellow when inliers is empty: no verdict); `caption` on a dark band at the top.
cv::Mat drawMatchOverlay(const cv::Mat& left, const std::vector<cv::KeyPoint>& left_keypoints,
                         const cv::Mat& right, const std::vector<cv::KeyPoint>& right_keypoints,
                         const std::vector<cv::DMatch>& matches, const std::vector<char>& inliers,
                         const std::string& caption);

}  // namespace risas

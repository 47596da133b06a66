// The feature methods the evaluation compares: RISAS and the paper's peers.
#pragma once

#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <memory>
#include <string>
#include <vector>

namespace risas::eval {

// What a method finds in one frame: keypoint pixels and one descriptor row
// each. The protocol, not the method, turns pixels into 3D points.
struct MethodOutput {
  std::vector<cv::Point2f> pixels;
  cv::Mat descriptors;
};

class FeatureMethod {
 public:
  virtual ~FeatureMethod() = default;
  virtual std::string name() const = 0;
  virtual int norm() const = 0;  // the distance its descriptors are matched with
  // Detect and describe, single-threaded. bgr: the frame's colour image.
  virtual MethodOutput run(const RgbdFrame& frame, const cv::Mat& bgr) const = 0;
};

// Which of a detector's keypoints a method describes.
enum class Keypoints {
  All,
  OnePerImagePoint,  // onePerImagePoint (metrics.hpp): each corner once, not once per pyramid level
};

// An OpenCV Feature2D's keypoints on `gray` (those `which` keeps) and their
// descriptors: ORB and ORB-distinct here and in risas_odometry.
void detectAndDescribe(cv::Feature2D& feature, const cv::Mat& gray, Keypoints which,
                       std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors);

// RISAS, ORB, SIFT, ORB+RISAS, ORB-distinct, ORB-distinct+RISAS, and with PCL:
// RISAS+CSHOT, ISS+CSHOT, UNIFORM+CSHOT, SIFT+CSHOT.
std::vector<std::string> methodNames();
bool havePcl();

// InputError for an unknown name or one that needs PCL in a build without it.
std::unique_ptr<FeatureMethod> makeMethod(const std::string& name, const RisasParams& params);

// RISAS with other parameters under another name (the parameter studies).
std::unique_ptr<FeatureMethod> makeRisas(const std::string& name, const RisasParams& params);

// The PCL peers (methods_pcl.cpp); nullptr for another name.
std::unique_ptr<FeatureMethod> makePclMethod(const std::string& name, const RisasParams& params);

}  // namespace risas::eval

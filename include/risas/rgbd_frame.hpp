// One registered RGB-D frame, validated and converted once on construction.
#pragma once

#include "risas/intrinsics.hpp"

#include <opencv2/core.hpp>

#include <string>

namespace risas {

// Channel order of a 3- or 4-channel colour image (OpenCV's imread gives BGR,
// ROS rgb8 gives RGB). Only the grey conversion weights depend on it.
enum class ColorOrder { BGR, RGB };

class RgbdFrame {
 public:
  RgbdFrame() = default;
  // color: CV_8UC1 (grey), CV_8UC3 or CV_8UC4.
  // depth: CV_16UC1 in millimetres (0 = missing) or CV_32FC1 in metres
  //        (non-finite or <= 0 = missing), same size as color, registered.
  // Depth beyond kMaxDepth metres is no measurement of an RGB-D camera and
  // counts as missing. Throws InputError (naming the problem) on empty
  // images, frames smaller than kMinSide x kMinSide, a size mismatch, an
  // unsupported type, bad intrinsics (Intrinsics::validate with the size)
  // or a depth image with no valid pixel.
  static constexpr float kMaxDepth = 100.0f;
  static constexpr int kMinSide = 2;
  RgbdFrame(const cv::Mat& color, const cv::Mat& depth, const Intrinsics& intrinsics,
            ColorOrder order = ColorOrder::BGR);

  const cv::Mat& gray() const { return gray_; }    // CV_8UC1
  const cv::Mat& depth() const { return depth_; }  // CV_32FC1 metres, NaN = missing
  const Intrinsics& intrinsics() const { return intrinsics_; }
  cv::Size size() const { return gray_.size(); }
  bool empty() const { return gray_.empty(); }

 private:
  cv::Mat gray_;
  cv::Mat depth_;
  Intrinsics intrinsics_;
};

// Depth in metres, NaN where missing: 16UC1 millimetres and 32FC1 metres go
// through one templated path (as depth_image_proc does).
cv::Mat depthToMetres(const cv::Mat& depth);

// An image's type in words, for errors: "16-bit, 3 channels (CV_16UC3)".
std::string describeType(const cv::Mat& image);

}  // namespace risas

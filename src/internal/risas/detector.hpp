// The RISAS keypoint detector (paper III-A).
#pragma once

#include "risas/geometry.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace risas {

class Detector {
 public:
  explicit Detector(const DetectorParams& params = DetectorParams());

  // Keypoints: local maxima of the eq. 1 response above the threshold, on
  // pixels with a surface normal (and non-zero mask, if given), at most
  // max_keypoints spread over the image. KeyPoint::size is the diameter of
  // the detection window, angle is -1 (the descriptor sets both), response
  // is eq. 1's Harris measure. Const and reentrant.
  void detect(const RgbdFrame& frame, const FrameGeometry& geometry, std::vector<cv::KeyPoint>& keypoints,
              const cv::Mat& mask = cv::Mat()) const;

  // The Harris response of eq. 1: the structure tensor of the grey image I
  // and the dot-product image P weighted tau : (1 - tau), then
  // det(M) - k trace(M)^2. CV_32FC1.
  cv::Mat response(const RgbdFrame& frame, const FrameGeometry& geometry) const;

  const DetectorParams& params() const { return params_; }

 private:
  // R into R's buffer; returns the largest R.
  float computeResponse(const RgbdFrame& frame, const FrameGeometry& geometry, cv::Mat& R) const;

  DetectorParams params_;
  // The grey blur's and the window's Gaussian kernels (centre and one side),
  // made once from the parameters.
  std::vector<float> gray_half_, window_half_;
};

// Keeps the best `max_count` keypoints by response, spread over a
// grid_cols x grid_rows grid: each cell first gets an equal share of its own
// best, the rest of the budget goes to the best remaining anywhere.
void retainBestSpread(std::vector<cv::KeyPoint>& keypoints, int max_count, cv::Size image_size, int grid_cols,
                      int grid_rows);

}  // namespace risas

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

  // The response of eq. 1 (autocorrelationResponse) over the frame. CV_32FC1.
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

// Eq. 1 of the paper (eq::autocorrelation), readable. The autocorrelation
//   E(u,v) = sum_w tau [I_grayscale(x+u, y+v) - I_grayscale(x,y)]^2
//            + (1 - tau) [I_dp(x+u, y+v) - I_dp(x,y)]^2
// is, to second order, [u v] M [u v]^T with the structure tensor
//   M = w * ( tau grad I_grayscale grad I_grayscale^T + (1 - tau) grad I_dp grad I_dp^T ),
// gradients by Sobel scaled 1/8 (border replicated), w a Gaussian of
// params.window_sigma (border reflected), and the response is Harris's
// det(M) - k trace(M)^2 (k = params.harris_k). I_grayscale: the grey image
// blurred with gray_sigma; I_dp: the dot-product image (eq. 2,
// dotProductImage); CV_32FC1 of one size. Detector uses it when
// cv::useOptimized() is false, else its kernel (kernels/autocorrelation_rows),
// equal to it within float rounding.
cv::Mat autocorrelationResponse(const cv::Mat& I_grayscale, const cv::Mat& I_dp, const DetectorParams& params);

// Keeps the best `max_count` keypoints by response, spread over a
// grid_cols x grid_rows grid: each cell first gets an equal share of its own
// best, the rest of the budget goes to the best remaining anywhere.
void retainBestSpread(std::vector<cv::KeyPoint>& keypoints, int max_count, cv::Size image_size, int grid_cols,
                      int grid_rows);

}  // namespace risas

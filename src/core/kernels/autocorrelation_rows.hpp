// The fast kernel of eq. 1: risas::autocorrelationResponse (detector.hpp)
// computed row by row, fused, in parallel stripes. Held equal to the readable
// function by Detector.ResponseIsEquationOneOnEveryPath.
#pragma once

#include <opencv2/core.hpp>

#include <vector>

namespace risas {

// R (CV_32FC1, gray's size) = autocorrelationResponse(I_grayscale, I_dp) with
// I_grayscale = gray (CV_8UC1) blurred by the half kernel gray_half
// (gaussianHalfKernel, reflected border) and I_dp = P_grid (the dot-product
// image on the normals' grid of step normal_stride) enlarged bilinearly as
// dotProductImage does; window_half is w's half kernel. Returns R's largest
// value.
float autocorrelationRows(const cv::Mat& gray, const std::vector<float>& gray_half, const cv::Mat& P_grid,
                          int normal_stride, const std::vector<float>& window_half, float tau, float k, cv::Mat& R);

}  // namespace risas

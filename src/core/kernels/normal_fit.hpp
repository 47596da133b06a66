// The fast kernel of the normals: risas::estimateNormals (geometry.hpp,
// normals.cpp) computed from box sums of the point moments (O(1) per point
// away from jumps, as PCL's integral-image estimation), in float, in
// parallel bands of rows. Held equal to the readable fit by
// Geometry.NormalsAreTheWindowedFitOnEveryPath.
#pragma once

#include "risas/geometry.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace risas {

// estimateNormals's outputs for the same inputs; normals within float
// rounding of the readable fit's (hundredths of a degree), on_block_surface
// the same.
void normalFitKernel(const cv::Mat& depth_metres, const std::vector<float>& x_factor,
                     const std::vector<float>& y_factor, const GeometryParams& params, cv::Mat& normals,
                     cv::Mat& on_block_surface);

}  // namespace risas

// Paper III-A steps 2-4: the main normal of a frame and the dot-product image.
#pragma once

#include "risas/geometry.hpp"

#include <opencv2/core.hpp>

namespace risas {

// Sector label (0 .. n_s - 1) of each of the angles between a unit normal and
// the camera x, y and z axes, the angle range [0, pi] cut into n_s sectors
// (paper: n = [1,1,1]/sqrt(3) -> 54.7 deg each -> labels [2,2,2] 1-based).
cv::Vec3i normalLabels(const cv::Vec3f& normal, int n_s);

// The most frequent label triple over all normals (of the blocks, see
// FrameGeometry) defines
// n_main. The paper leaves open how labels become a vector; the reference took
// the sector edges, which is not a unit vector. Here n_main is the mean of the
// normals carrying the most frequent triple: inside that triple's sectors,
// unit, and stable under noise. (0, 0, -1) when no pixel has a normal.
cv::Vec3f computeMainNormal(const cv::Mat& normals, int n_s);

// P = 255 |n_main . n|, the dot products on the grey image's [0, 255] scale so
// that tau weighs two channels of the same range in eq. 1. Pixels without a
// normal take a Gaussian-weighted mean of their neighbours' P (normalised
// convolution with sigma, which also smooths P) so depth holes create no
// artificial gradients. P is smooth, so it is formed on the normals' grid,
// one value per block, filtered with sigma / normal_stride (the kernel cut
// at 3 sigma, the border replicated): dotProductGrid, CV_32FC1 of the
// normals' size. dotProductImage enlarges it to the frame bilinearly (as
// cv::resize's INTER_LINEAR), CV_32FC1 in P. The outputs' buffers are
// reused when they already have the size and type.
void dotProductGrid(const FrameGeometry& geometry, const cv::Vec3f& n_main, double sigma, cv::Mat& grid);
void dotProductImage(const FrameGeometry& geometry, const cv::Vec3f& n_main, double sigma, cv::Mat& P);

}  // namespace risas

// Files: intrinsics, RGB-D frames from PNG, features in cv::FileStorage.
// Every reader throws InputError with the path and what is wrong with it.
#pragma once

#include "risas/features.hpp"
#include "risas/intrinsics.hpp"
#include "risas/rgbd_frame.hpp"

#include <string>

namespace risas {

// A 3x3 camera matrix as nine numbers in text, row by row (the
// ManipulatorsDataset's camera-intrinsics.txt).
Intrinsics readIntrinsicsFile(const std::string& path);

// Colour (8-bit, read as BGR) and 16-bit millimetre depth images.
RgbdFrame loadRgbdFrame(const std::string& color_path, const std::string& depth_path, const Intrinsics& intrinsics);

// Nodes: descriptor_type ("RISAS"), keypoints (cv::write of the
// std::vector<cv::KeyPoint>, 0-based pixels), descriptors (N x D CV_32F),
// points3d and normals (N x 3 CV_32F, metres / unit), support_radius (N x 1).
// .yml, .yaml, .xml or .json, by the extension, as cv::FileStorage does.
void writeFeatures(const std::string& path, const Features& features);
Features readFeatures(const std::string& path);

}  // namespace risas

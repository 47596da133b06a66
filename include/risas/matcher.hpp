// Nearest-neighbour distance ratio matching (paper IV-A).
#pragma once

#include "risas/params.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace risas {

// For each query row, its nearest train row (L2 distance for CV_32F
// descriptors, Hamming for binary CV_8U ones such as ORB's), kept when
// nearest / second-nearest < ratio (a train set of one row has no second
// neighbour and always passes). With cross_check the train row's own nearest
// query row must be the query as well. DMatch: queryIdx, trainIdx, distance.
// Throws InputError when the descriptors differ in width or type, or are
// neither CV_32F nor CV_8U.
std::vector<cv::DMatch> matchDescriptors(const cv::Mat& query, const cv::Mat& train,
                                         const MatchParams& params = MatchParams());

// Nearest and second-nearest train neighbour of every query row (the raw
// material of NNDR, e.g. to sweep the ratio). Empty inner vectors for none.
std::vector<std::vector<cv::DMatch>> nearestTwo(const cv::Mat& query, const cv::Mat& train);

}  // namespace risas

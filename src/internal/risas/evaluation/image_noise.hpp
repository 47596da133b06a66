// Grey noise added to a recording's colour images, as a camera's gain adds
// it in dim light: to measure how far a result moves under noise the eye
// cannot see, or under more (docs/odometry.md, "The trajectories under
// imperceptible noise").
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>

namespace risas::eval {

// `image` (8-bit, any number of channels) plus zero-mean Gaussian noise of
// standard deviation `sigma` grey levels, drawn independently for each
// channel of each pixel, rounded and saturated to 0..255. The draw depends
// on (seed, index) alone: the same frame gets the same noise wherever it is
// read, another seed other noise. sigma 0 returns the image unchanged.
// InputError for a sigma that is negative, not finite or above 255, or an
// image that is not 8-bit.
cv::Mat withImageNoise(const cv::Mat& image, double sigma, uint32_t seed, uint64_t index);

}  // namespace risas::eval

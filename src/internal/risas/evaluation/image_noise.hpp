// Grey noise added to a recording's colour images, as a camera's gain adds
// it in dim light: to measure how far a result moves under noise the eye
// cannot see, or under more (docs/odometry.md, "The trajectories under
// imperceptible noise").
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <string>

namespace risas::eval {

// The noise a tool is asked for (--image-noise, --noise-seed): sigma grey
// levels, 0 for none, drawn as `seed` says.
struct ImageNoise {
  double sigma = 0.0;
  uint32_t seed = 0;
  bool sigmaValid() const;  // sigma is finite and 0 to 255
  void validate() const;    // InputError unless sigmaValid()
};

// `image` (8-bit, any number of channels) plus zero-mean Gaussian noise of
// standard deviation `sigma` grey levels, drawn independently for each
// channel of each pixel, rounded and saturated to 0..255. The draw depends
// on (seed, index) alone: the same frame gets the same noise wherever it is
// read, another seed other noise. sigma 0 returns the image unchanged.
// InputError for a sigma that is negative, not finite or above 255, or an
// image that is not 8-bit.
cv::Mat withImageNoise(const cv::Mat& image, double sigma, uint32_t seed, uint64_t index);

// An index for withImageNoise from an image's name (64-bit FNV-1a of its
// bytes): images without a frame number get noise of their own, the same
// wherever the name is the same.
uint64_t imageNoiseIndex(const std::string& name);

}  // namespace risas::eval

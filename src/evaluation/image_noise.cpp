#include "risas/evaluation/image_noise.hpp"

#include "risas/errors.hpp"
#include "risas/rgbd_frame.hpp"

#include <cmath>
#include <string>

namespace risas::eval {

bool ImageNoise::sigmaValid() const { return std::isfinite(sigma) && sigma >= 0.0 && sigma <= 255.0; }

void ImageNoise::validate() const {
  if (!sigmaValid()) throw InputError("image noise sigma must be 0 to 255 grey levels, got " + std::to_string(sigma));
}

cv::Mat withImageNoise(const cv::Mat& image, double sigma, uint32_t seed, uint64_t index) {
  ImageNoise{sigma, seed}.validate();
  if (image.depth() != CV_8U) {
    throw InputError("image noise is for 8-bit images, got " + describeType(image));
  }
  if (sigma == 0.0) return image.clone();
  // cv::RNG's state is 64 bits: the seed in the high half, the index in the
  // low; splitmix64's finaliser spreads neighbouring frames' states apart.
  uint64_t state = (static_cast<uint64_t>(seed) << 32) ^ index;
  state = (state ^ (state >> 30)) * 0xbf58476d1ce4e5b9ULL;
  state = (state ^ (state >> 27)) * 0x94d049bb133111ebULL;
  state ^= state >> 31;
  cv::RNG rng(state == 0 ? 1 : state);  // cv::RNG(0) would start from its default state
  cv::Mat noise(image.size(), CV_MAKETYPE(CV_32F, image.channels()));
  rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
  cv::Mat sum;
  image.convertTo(sum, noise.type());
  sum += noise;
  cv::Mat noisy;
  sum.convertTo(noisy, image.type());  // rounds, and saturates at 0 and 255
  return noisy;
}

uint64_t imageNoiseIndex(const std::string& name) {
  uint64_t hash = 0xcbf29ce484222325ULL;
  for (const char c : name) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

}  // namespace risas::eval

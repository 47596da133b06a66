// --image-noise and --noise-seed, for the tools that measure on a recording
// as a noisier camera would see it (risas_odometry, risas_evaluate): the
// same options, checks and report line in each.
#pragma once

#include "cli.hpp"

#include "risas/evaluation/image_noise.hpp"

#include <iostream>
#include <string>
#include <vector>

namespace risas::cli {

// same_draw: where the same image gets the same noise, for the seed's help.
inline std::vector<Option> imageNoiseOptions(const std::string& same_draw) {
  return {{"image-noise", "SIGMA",
           "add zero-mean Gaussian noise of SIGMA grey levels to each channel of each colour image before its "
           "features, as dim light does (default 0: none); 1 is below a Kinect's own noise"},
          {"noise-seed", "N", "the noise's draw: another N, other noise; " + same_draw + " (default 0)"}};
}

// The noise asked for; UsageError for a sigma outside 0..255 or a seed
// without a sigma.
inline eval::ImageNoise imageNoiseFrom(const Args& args) {
  eval::ImageNoise noise;
  noise.sigma = args.getDouble("image-noise", 0.0);
  if (!noise.sigmaValid()) {
    throw UsageError("--image-noise is 0 to 255 grey levels, not " + args.get("image-noise"));
  }
  noise.seed = static_cast<uint32_t>(args.getInt("noise-seed", 0, 0, 1000000000));
  if (noise.sigma == 0.0) args.refuse({"noise-seed"}, "without --image-noise");
  return noise;
}

// Says on standard output that the images are noisier than recorded.
inline void noteImageNoise(const eval::ImageNoise& noise) {
  if (noise.sigma > 0.0) {
    std::cout << "Colour images with grey noise of sigma " << noise.sigma << " (noise seed " << noise.seed
              << ") before their features\n";
  }
}

}  // namespace risas::cli

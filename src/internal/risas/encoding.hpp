// Paper III-B-3: descriptor construction, the n_pie x n_bin x (n_vec + 1)
// histogram of spatial sector, intensity rank and normal dot-product labels.
#pragma once

#include "risas/geometry.hpp"
#include "risas/neighbourhood.hpp"
#include "risas/params.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace risas {

// The grey image at the coarser scales a patch's samples may need (see
// DescriptorParams::sample_blur): level 0 is the frame's grey image, each
// next level cv::pyrDown of the one before (a 5-tap Gaussian of sigma 1 in
// the finer level's pixels, then every second pixel). So level l is the grey
// image blurred by sigma_l = sqrt((4^l - 1) / 3) pixels (0, 1, 2.24, 4.58)
// and sampled every 2^l pixels; its pixel (i, j) lies at (2^l i, 2^l j) of
// level 0.
struct GreyPyramid {
  static constexpr int kMaxLevels = 4;
  cv::Mat level[kMaxLevels];
  int levels = 0;
  // The grey image's noise the intensity ranks allow for (grey levels, a
  // standard deviation; DescriptorParams::grey_noise as resolved for the
  // frame). 0: exact ranks.
  float noise = 0.0f;
};

// The pyramid of `gray` with `levels` levels (at least 1, at most
// kMaxLevels, fewer where a level would be smaller than 2 x 2). Level 0 is a
// header of `gray`; the others are written into `pyramid`'s own buffers,
// reused when their size has not changed.
void buildGreyPyramid(const cv::Mat& gray, int levels, GreyPyramid& pyramid);

// lambda, the fractional pyramid level at which the samples of a disc of
// radius_px read the grey image: where the pyramid's blur is sample_blur
// times the samples' spacing s = radius_px / patch_radius, so that the
// samples see the surface's grey pattern equally smoothed at every distance
// and do not alias it. Inverting sigma_l: lambda = log4(1 + 3 (sample_blur
// s)^2), clamped to [0, levels - 1]. 0 when sample_blur is 0: the frame's
// own grey image, the paper's sampling.
float sampleLevel(float radius_px, const DescriptorParams& params, int levels);

// The fractional level whose blur is sigma_px level-0 pixels,
// log4(1 + 3 sigma_px^2), clamped to [0, levels - 1]: sampleLevel's and
// gradientOrientation's.
float blurLevel(double sigma_px, int levels);

// gradientOrientation reads its samples where the pyramid's blur is this many
// sample spacings (SIFT takes its orientation histogram on the level whose
// blur is 1.6 of that level's pixels): the gradients of samples one spacing
// apart then see the grey pattern smooth enough not to turn with its noise.
constexpr double kOrientationBlur = 1.5;

// The levels sampleLevel and gradientOrientation can ask for with these
// parameters, at most.
int pyramidLevelsNeeded(const DescriptorParams& params);

// The grey value at level-0 point (x, y) read at fractional level lambda:
// bilinear on level floor(lambda) and, when lambda has a fraction f, on the
// next level too, the two blended (1 - f, f), as trilinear mipmapping does.
// Points are clamped into each level.
float greyAt(const GreyPyramid& pyramid, float lambda, float x, float y);

class PatchEncoder {
 public:
  explicit PatchEncoder(const DescriptorParams& params);

  int dimension() const { return params_.dimension(); }

  // Samples the disc of radius radius_px around the keypoint, rotated by
  // theta, on a fixed grid of patch_radius samples per radius (so patches of
  // any size give comparable histograms), its grey values read from `grey`
  // at sampleLevel(radius_px); a sample counts when it is foreground (eq. 5)
  // with a normal. Each gets
  //   spatial label:   its sector of n_pie equal sectors, measured from theta;
  //   intensity label: its rank group among the patch's intensities, n_bin groups;
  //   shape label:     rho = |n_k . n_i| (eq. 8); rho >= rho_threshold is one
  //                    label, the rest fall into n_vec rank groups.
  // With soft_binning a sample's vote is split between its two nearest rank
  // groups by its mid-rank under grey.noise (rankPositionTable); sector and
  // shape label stay one each. The histogram is L2-normalised into `out`
  // (dimension() floats). False when fewer than min_valid_fraction of the
  // samples count.
  bool encode(const GreyPyramid& grey, const FrameGeometry& geometry, const Neighbourhood& neighbourhood,
              float radius_px, double theta, float* out) const;

 private:
  DescriptorParams params_;
  // The disc's samples: offset (i, j) in units of the disc radius, and
  // spatial label in the rotated patch.
  std::vector<float> disc_i_, disc_j_;
  std::vector<uint16_t> disc_sector_;  // ring * n_pie + sector
};

}  // namespace risas

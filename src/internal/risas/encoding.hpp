// Paper III-B-3: descriptor construction, the n_pie x n_bin x (n_vec + 1)
// histogram of spatial sector, intensity rank and normal dot-product labels.
#pragma once

#include "risas/geometry.hpp"
#include "risas/neighbourhood.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <cstdint>
#include <vector>

namespace risas {

class PatchEncoder {
 public:
  explicit PatchEncoder(const DescriptorParams& params);

  int dimension() const { return params_.dimension(); }

  // Samples the disc of radius radius_px around the keypoint, rotated by
  // theta, on a fixed grid of patch_radius samples per radius (so patches of
  // any size give comparable histograms); a sample counts when it is
  // foreground (eq. 5) with a normal. Each gets
  //   spatial label:   its sector of n_pie equal sectors, measured from theta;
  //   intensity label: its rank group among the patch's intensities, n_bin groups;
  //   shape label:     rho = |n_k . n_i| (eq. 8); rho >= rho_threshold is one
  //                    label, the rest fall into n_vec rank groups.
  // With soft_binning a sample's vote is split between its two nearest rank
  // groups by its mid-rank (rankPositionTable); sector and shape label stay
  // one each. The histogram is L2-normalised into `out` (dimension() floats). False
  // when fewer than min_valid_fraction of the samples count.
  bool encode(const RgbdFrame& frame, const FrameGeometry& geometry, const Neighbourhood& neighbourhood,
              float radius_px, double theta, float* out) const;

 private:
  DescriptorParams params_;
  // The disc's samples: offset (i, j) in units of the disc radius, and
  // spatial label in the rotated patch.
  std::vector<float> disc_i_, disc_j_;
  std::vector<uint16_t> disc_sector_;  // ring * n_pie + sector
};

}  // namespace risas

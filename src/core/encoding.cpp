#include "risas/encoding.hpp"

#include "risas/ranking.hpp"

#include "normal_stride.hpp"

#include <algorithm>
#include <cmath>

namespace risas {

PatchEncoder::PatchEncoder(const DescriptorParams& params) : params_(params) {
  params_.validate();
  const int r = params_.patch_radius;
  const double sector_angle = 2.0 * CV_PI / params_.n_pie;
  for (int j = -r; j <= r; ++j) {
    for (int i = -r; i <= r; ++i) {
      if (i * i + j * j > r * r) continue;
      double angle = std::atan2(static_cast<double>(j), static_cast<double>(i));
      if (angle < 0.0) angle += 2.0 * CV_PI;
      const int sector = std::min(params_.n_pie - 1, static_cast<int>(angle / sector_angle));
      disc_.push_back({static_cast<float>(i) / r, static_cast<float>(j) / r, sector});
    }
  }
}

bool PatchEncoder::encode(const RgbdFrame& frame, const FrameGeometry& geometry, const Neighbourhood& nb,
                          float radius_px, double theta, float* out) const {
  const cv::Mat& gray = frame.gray();
  const float max_u = static_cast<float>(gray.cols - 1), max_v = static_cast<float>(gray.rows - 1);
  const float cu = nb.centre.x, cv_ = nb.centre.y;
  const float cos_t = static_cast<float>(std::cos(theta)) * radius_px;
  const float sin_t = static_cast<float>(std::sin(theta)) * radius_px;
  const cv::Vec3f k(static_cast<float>(nb.point.x()), static_cast<float>(nb.point.y()),
                    static_cast<float>(nb.point.z()));
  const cv::Vec3f n_k(static_cast<float>(nb.normal.x()), static_cast<float>(nb.normal.y()),
                      static_cast<float>(nb.normal.z()));
  const float t2 = static_cast<float>(params_.background_distance * params_.background_distance);
  const float rho_bar = static_cast<float>(params_.rho_threshold);
  constexpr int kRhoLevels = 256;

  // The counted samples, in a per-thread buffer reused across keypoints.
  struct Sample {
    uint8_t sector, intensity;
    uint16_t rho_level;  // kRhoLevels for a flat sample (rho >= rho-bar)
  };
  thread_local std::vector<Sample> samples;
  samples.resize(disc_.size());
  int counted = 0;
  // rho_count[kRhoLevels] counts the flat samples, which are not ranked.
  int intensity_count[256] = {}, rho_count[kRhoLevels + 1] = {};
  withNormalStride(geometry.normal_stride, [&](auto stride) {
    for (const DiscSample& s : disc_) {
      // Patch x axis along theta, y axis 90 degrees on (image v points down).
      const float x = cu + cos_t * s.i - sin_t * s.j;
      const float y = cv_ + sin_t * s.i + cos_t * s.j;
      if (!(x >= 0.0f && y >= 0.0f && x <= max_u && y <= max_v)) continue;
      const int u = cvRound(x), v = cvRound(y);  // not negative
      // FrameGeometry::hasNormal and normal, with the stride's division
      // compiled to a shift for the default stride.
      if (!geometry.on_block_surface.at<uchar>(v, u)) continue;
      const unsigned block_stride = stride;
      const cv::Vec3f& n = geometry.normals.at<cv::Vec3f>(static_cast<unsigned>(v) / block_stride,
                                                          static_cast<unsigned>(u) / block_stride);
      if (n[2] == 0.0f) continue;  // also no point
      const cv::Vec3f d = geometry.point(v, u) - k;
      if (d.dot(d) >= t2) continue;  // background (eq. 5)

      const int u0 = std::min(static_cast<int>(x), gray.cols - 2);
      const int v0 = std::min(static_cast<int>(y), gray.rows - 2);
      const float a = x - u0, b = y - v0;
      const uchar* row0 = gray.ptr<uchar>(v0);
      const uchar* row1 = gray.ptr<uchar>(v0 + 1);
      const float intensity =
          (1 - b) * ((1 - a) * row0[u0] + a * row0[u0 + 1]) + b * ((1 - a) * row1[u0] + a * row1[u0 + 1]);
      const uint8_t level = static_cast<uint8_t>(intensity + 0.5f);  // rounded; intensity is in [0, 255]

      // Shape: the flat majority (rho >= rho-bar) is one label; the rest are
      // ranked on kRhoLevels levels of rho / rho-bar. (Both computed, one
      // selected: whether a sample is flat is not predictable.)
      const float rho = std::abs(n_k.dot(n));
      const int ranked = std::min(kRhoLevels - 1, static_cast<int>(rho / rho_bar * kRhoLevels));
      const uint16_t rho_level = static_cast<uint16_t>(rho >= rho_bar ? kRhoLevels : ranked);
      samples[static_cast<size_t>(counted++)] = {static_cast<uint8_t>(s.sector), level, rho_level};
      ++intensity_count[level];
      ++rho_count[rho_level];
    }
  });
  if (counted < params_.min_valid_fraction * disc_.size() || counted < 3) return false;

  // Rank groups by counting sort: a sample's group depends only on its
  // level, so each level's group is tabulated once.
  uint8_t intensity_label[256], shape_label[kRhoLevels + 1];
  rankGroupTable(intensity_count, 256, params_.n_bin, intensity_label);
  rankGroupTable(rho_count, kRhoLevels, params_.n_vec, shape_label);
  shape_label[kRhoLevels] = static_cast<uint8_t>(params_.n_vec);

  const int n_bin = params_.n_bin, n_shape = params_.n_vec + 1;
  std::fill(out, out + dimension(), 0.0f);
  for (int i = 0; i < counted; ++i) {
    const Sample& sample = samples[static_cast<size_t>(i)];
    ++out[(sample.sector * n_bin + intensity_label[sample.intensity]) * n_shape + shape_label[sample.rho_level]];
  }
  float norm = 0.0f;
  for (int d = 0; d < dimension(); ++d) norm += out[d] * out[d];
  const float inv = 1.0f / std::sqrt(norm);
  for (int d = 0; d < dimension(); ++d) out[d] *= inv;
  return true;
}

}  // namespace risas

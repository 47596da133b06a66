#include "risas/encoding.hpp"

#include "risas/ranking.hpp"

#include "with_default.hpp"

#include <opencv2/core/hal/intrin.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

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
      disc_i_.push_back(static_cast<float>(i) / r);
      disc_j_.push_back(static_cast<float>(j) / r);
      disc_sector_.push_back(static_cast<uint8_t>(sector));
    }
  }
  disc_size_ = static_cast<int>(disc_i_.size());
  // Whole fours; the padding's NaN offsets fall outside every image.
  const size_t padded = (disc_i_.size() + 3) / 4 * 4;
  disc_i_.resize(padded, std::numeric_limits<float>::quiet_NaN());
  disc_j_.resize(padded, std::numeric_limits<float>::quiet_NaN());
  disc_sector_.resize(padded, 0);
}

bool PatchEncoder::encode(const RgbdFrame& frame, const FrameGeometry& geometry, const Neighbourhood& nb,
                          float radius_px, double theta, float* out) const {
  using cv::v_float32x4;
  using cv::v_int32x4;
  const cv::Mat& gray = frame.gray();
  const int cols = gray.cols, rows = gray.rows;
  const float cos_t = static_cast<float>(std::cos(theta)) * radius_px;
  const float sin_t = static_cast<float>(std::sin(theta)) * radius_px;
  const float t2 = static_cast<float>(params_.background_distance * params_.background_distance);
  const float rho_bar = static_cast<float>(params_.rho_threshold);
  constexpr int kRhoLevels = 256;
  const auto all = [](double value) { return cv::v_setall_f32(static_cast<float>(value)); };
  const v_float32x4 cu = all(nb.centre.x), cv_ = all(nb.centre.y), vcos = all(cos_t), vsin = all(sin_t);
  const v_float32x4 max_u = all(cols - 1), max_v = all(rows - 1), zero = cv::v_setzero_f32(), one = all(1.0);
  const v_float32x4 kx = all(nb.point.x()), ky = all(nb.point.y()), kz = all(nb.point.z());
  const v_float32x4 nkx = all(nb.normal.x()), nky = all(nb.normal.y()), nkz = all(nb.normal.z());
  const v_int32x4 last_col = cv::v_setall_s32(cols - 1), last_row = cv::v_setall_s32(rows - 1);
  const v_int32x4 last_u0 = cv::v_setall_s32(cols - 2), last_v0 = cv::v_setall_s32(rows - 2);
  const v_int32x4 first = cv::v_setzero_s32();

  // The counted samples, in a per-thread buffer reused across keypoints.
  struct Sample {
    uint8_t sector, intensity;
    uint16_t rho_level;  // kRhoLevels for a flat sample (rho >= rho-bar)
  };
  thread_local std::vector<Sample> samples;
  samples.resize(disc_i_.size());
  int counted = 0;
  // rho_count[kRhoLevels] counts the flat samples, which are not ranked.
  int intensity_count[256] = {}, rho_count[kRhoLevels + 1] = {};
  // Four samples at a time: the arithmetic in lanes, each lane's look-ups
  // (its pixel's surface flag, block normal, depth and 2 x 2 grey values)
  // gathered one by one. Out-of-image lanes read a clamped pixel and are
  // dropped.
  withDefault<GeometryParams::kDefaultNormalStride>(geometry.normal_stride, [&](auto stride) {
    for (size_t s = 0; s < disc_i_.size(); s += 4) {
      const v_float32x4 di = cv::v_load(&disc_i_[s]), dj = cv::v_load(&disc_j_[s]);
      // Patch x axis along theta, y axis 90 degrees on (image v points down).
      const v_float32x4 x = cu + vcos * di - vsin * dj;
      const v_float32x4 y = cv_ + vsin * di + vcos * dj;
      const v_float32x4 inside = (x >= zero) & (y >= zero) & (x <= max_u) & (y <= max_v);
      // The nearest pixel (cvRound), and the bilinear cell's corner.
      int u[4], v[4], u0[4], v0[4];
      cv::v_store(u, cv::v_max(cv::v_min(cv::v_round(x), last_col), first));
      cv::v_store(v, cv::v_max(cv::v_min(cv::v_round(y), last_row), first));
      cv::v_store(u0, cv::v_max(cv::v_min(cv::v_trunc(x), last_u0), first));
      cv::v_store(v0, cv::v_max(cv::v_min(cv::v_trunc(y), last_v0), first));
      float on[4], nx[4], ny[4], nz[4], z[4], xf[4], yf[4], g00[4], g01[4], g10[4], g11[4];
      for (int l = 0; l < 4; ++l) {
        on[l] = geometry.on_block_surface.at<uchar>(v[l], u[l]);
        const unsigned block_stride = stride;  // a shift for the default stride
        const cv::Vec3f& n = geometry.normals.at<cv::Vec3f>(static_cast<unsigned>(v[l]) / block_stride,
                                                            static_cast<unsigned>(u[l]) / block_stride);
        nx[l] = n[0], ny[l] = n[1], nz[l] = n[2];
        z[l] = geometry.depth.at<float>(v[l], u[l]);
        xf[l] = geometry.x_factor[static_cast<size_t>(u[l])];
        yf[l] = geometry.y_factor[static_cast<size_t>(v[l])];
        const uchar* row0 = gray.ptr<uchar>(v0[l]) + u0[l];
        const uchar* row1 = row0 + gray.step;
        g00[l] = row0[0], g01[l] = row0[1], g10[l] = row1[0], g11[l] = row1[1];
      }
      const v_float32x4 vz = cv::v_load(z), vnx = cv::v_load(nx), vny = cv::v_load(ny), vnz = cv::v_load(nz);
      // On its block's surface with a normal (FrameGeometry::hasNormal), and
      // not background (eq. 5).
      const v_float32x4 dx = cv::v_load(xf) * vz - kx, dy = cv::v_load(yf) * vz - ky, dz = vz - kz;
      const v_float32x4 counts = inside & (cv::v_load(on) != zero) & (vnz != zero) &
                                 (dx * dx + dy * dy + dz * dz < all(t2));
      const int lanes = cv::v_signmask(counts);
      if (lanes == 0) continue;

      const v_float32x4 a = x - cv::v_cvt_f32(cv::v_load(u0)), b = y - cv::v_cvt_f32(cv::v_load(v0));
      const v_float32x4 intensity = (one - b) * ((one - a) * cv::v_load(g00) + a * cv::v_load(g01)) +
                                    b * ((one - a) * cv::v_load(g10) + a * cv::v_load(g11));
      int level[4], rho_level[4];
      cv::v_store(level, cv::v_trunc(intensity + all(0.5)));  // rounded; intensity is in [0, 255]
      // Shape: the flat majority (rho >= rho-bar) is one label; the rest are
      // ranked on kRhoLevels levels of rho / rho-bar.
      const v_float32x4 rho = cv::v_abs(nkx * vnx + nky * vny + nkz * vnz);
      const v_int32x4 ranked = cv::v_min(cv::v_trunc(rho / all(rho_bar) * all(kRhoLevels)),
                                         cv::v_setall_s32(kRhoLevels - 1));
      cv::v_store(rho_level, cv::v_select(cv::v_reinterpret_as_s32(rho >= all(rho_bar)),
                                          cv::v_setall_s32(kRhoLevels), ranked));
      for (int l = 0; l < 4; ++l) {
        if (!(lanes >> l & 1)) continue;
        samples[static_cast<size_t>(counted++)] = {disc_sector_[s + static_cast<size_t>(l)],
                                                    static_cast<uint8_t>(level[l]),
                                                    static_cast<uint16_t>(rho_level[l])};
        ++intensity_count[level[l]];
        ++rho_count[rho_level[l]];
      }
    }
  });
  if (counted < params_.min_valid_fraction * disc_size_ || counted < 3) return false;

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

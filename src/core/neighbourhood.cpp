#include "risas/neighbourhood.hpp"

#include <Eigen/Eigenvalues>
#include <opencv2/core/hal/intrin.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

namespace risas {

float depthScale(float depth) { return std::max(0.2f, (3.8f - 0.4f * std::max(2.0f, depth)) / 3.0f); }

float initialRadius(float s, float s_min, float s_max) {
  const float ratio = std::max(0.2f, s_max) / std::max(0.2f, s_min);
  return (-5.0f + 25.0f * std::min(3.0f, ratio)) * s;
}

float patchRadius(float depth, const ScaleRange& scales, double support_radius, const Intrinsics& intrinsics) {
  if (support_radius > 0.0) return static_cast<float>(0.5 * (intrinsics.fx + intrinsics.fy) * support_radius / depth);
  return initialRadius(depthScale(depth), scales.s_min, scales.s_max);
}

ScaleRange frameScaleRange(const cv::Mat& depth_metres) {
  CV_Assert(depth_metres.type() == CV_32FC1);
  // Depth histogram in centimetres up to 20 m: percentiles without a sort.
  constexpr int kBins = 2001;
  std::vector<int> histogram(kBins, 0);
  int total = 0;
  for (int r = 0; r < depth_metres.rows; ++r) {
    const float* d = depth_metres.ptr<float>(r);
    for (int c = 0; c < depth_metres.cols; ++c) {
      if (std::isnan(d[c])) continue;
      ++histogram[std::min(kBins - 1, static_cast<int>(d[c] * 100.0f))];
      ++total;
    }
  }
  if (total == 0) return {};
  const auto percentile = [&](double q) {
    const int target = static_cast<int>(q * (total - 1));
    int seen = 0;
    for (int b = 0; b < kBins; ++b) {
      seen += histogram[b];
      if (seen > target) return (b + 0.5f) / 100.0f;
    }
    return (kBins - 0.5f) / 100.0f;
  };
  return {depthScale(percentile(0.99)), depthScale(percentile(0.01))};
}

namespace {
// How many of four lanes a v_signmask sets (a popcount instruction is not in
// the baseline ISA).
constexpr int kLanesSet[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
}  // namespace

std::optional<Neighbourhood> selectNeighbourhood(const RgbdFrame& frame, const FrameGeometry& geometry,
                                                 const cv::Point2f& keypoint, float initial_radius_px,
                                                 double background_distance, bool with_intensity_centroid) {
  const int u0 = cvRound(keypoint.x), v0 = cvRound(keypoint.y);
  const cv::Size size = frame.size();
  if (u0 < 0 || v0 < 0 || u0 >= size.width || v0 >= size.height) return std::nullopt;
  if (!geometry.hasPoint(v0, u0) || !geometry.hasNormal(v0, u0)) return std::nullopt;

  Neighbourhood nb;
  nb.centre = keypoint;
  const cv::Vec3f k = geometry.point(v0, u0);
  const cv::Vec3f n = geometry.normal(v0, u0);
  nb.point = Eigen::Vector3d(k[0], k[1], k[2]);
  nb.normal = Eigen::Vector3d(n[0], n[1], n[2]);
  nb.initial_radius_px = initial_radius_px;

  const int radius = static_cast<int>(std::ceil(initial_radius_px));
  const float r2 = initial_radius_px * initial_radius_px;
  // Offsets from k_i are centimetres: float sums of a few thousand of them
  // keep far more precision than the depth has. Four pixels at a time, their
  // points formed in lanes from the depth and the back-projection factors.
  using cv::v_float32x4;
  const v_float32x4 kx = cv::v_setall_f32(k[0]), ky = cv::v_setall_f32(k[1]), kz = cv::v_setall_f32(k[2]);
  const v_float32x4 t2 = cv::v_setall_f32(static_cast<float>(background_distance * background_distance));
  v_float32x4 sx = cv::v_setzero_f32(), sy = sx, sz = sx, sxx = sx, sxy = sx, sxz = sx, syy = sx, syz = sx, szz = sx;
  // Per grey level: how many kept pixels have it, and the sum of their image
  // offsets. The rank-weighted centroid below needs nothing more.
  int count[256] = {};
  // Both offsets' sums in one integer, v's scaled by 2^32: one addition per
  // pixel instead of two. The u sum is the low 32 bits read as signed (the
  // multiples of 2^32 do not reach them), the v sum what remains over 2^32:
  // exact while each sum fits 32 bits, as two separate sums needed too.
  int64_t offsets[256] = {};
  // Pixels u .. u + 3 of row v0 + dv, their depths and x factors, those of
  // the lanes set in `in_disc`; their grey levels too with `with_centroid`
  // (a std::bool_constant, so that the loops without it have no branch).
  const auto accumulate = [&](auto with_centroid, const float* depth, const float* x_factor, float y_factor,
                              const uchar* gray, int u, int dv, const v_float32x4& in_disc) {
    const int64_t row_offset = static_cast<int64_t>(dv) * (int64_t{1} << 32);
    const v_float32x4 z = cv::v_load(depth);
    v_float32x4 x = cv::v_load(x_factor) * z - kx, y = cv::v_setall_f32(y_factor) * z - ky, dz = z - kz;
    // eq. 5: background beyond t (a NaN point compares false and is dropped)
    const v_float32x4 kept = ((x * x + y * y + dz * dz) < t2) & in_disc;
    x = x & kept, y = y & kept, dz = dz & kept;
    sx += x, sy += y, sz += dz;
    sxx += x * x, sxy += x * y, sxz += x * dz, syy += y * y, syz += y * dz, szz += dz * dz;
    const int lanes = cv::v_signmask(kept);
    nb.kept += kLanesSet[lanes];
    if constexpr (decltype(with_centroid)::value) {
      for (int i = 0; i < 4; ++i) {
        if (!(lanes >> i & 1)) continue;
        const uchar g = gray[u + i];
        ++count[g];
        offsets[g] += row_offset + (u + i - u0);
      }
    }
  };
  // first_lanes[n]: the first n of four lanes set.
  const v_float32x4 all_lanes = cv::v_reinterpret_as_f32(cv::v_setall_s32(-1));
  const v_float32x4 first_lanes[4] = {
      cv::v_setzero_f32(), cv::v_reinterpret_as_f32(cv::v_int32x4(-1, 0, 0, 0)),
      cv::v_reinterpret_as_f32(cv::v_int32x4(-1, -1, 0, 0)), cv::v_reinterpret_as_f32(cv::v_int32x4(-1, -1, -1, 0))};
  const auto sumDisc = [&](auto with_centroid) {
    for (int dv = std::max(-radius, -v0); dv <= std::min(radius, size.height - 1 - v0); ++dv) {
      const float row_r2 = r2 - static_cast<float>(dv * dv);
      if (row_r2 < 0.0f) continue;
      const int half = static_cast<int>(std::sqrt(row_r2));  // the disc's extent in this row
      const int v = v0 + dv, u_begin = std::max(u0 - half, 0), u_end = std::min(u0 + half, size.width - 1) + 1;
      const float* depth = geometry.depth.ptr<float>(v);
      const float* x_factor = geometry.x_factor.data();
      const float y_factor = geometry.y_factor[static_cast<size_t>(v)];
      const uchar* gray = frame.gray().ptr<uchar>(v);
      // The disc's rows are a row of the image apart: too far for the CPU's
      // own prefetching to see coming. Each row asks for the depth (and with
      // the centroid the grey) values of the row kPrefetchRows below at its
      // own extent, so they arrive while this one is summed. (A prefetch past
      // the image is dropped.)
      constexpr int kPrefetchRows = 2;
      if (v + kPrefetchRows < size.height) {
        const float* next_depth = geometry.depth.ptr<float>(v + kPrefetchRows);
        for (int u = u_begin; u < u_end + 16; u += 16) __builtin_prefetch(next_depth + u);
        if constexpr (decltype(with_centroid)::value) {
          const uchar* next_gray = frame.gray().ptr<uchar>(v + kPrefetchRows);
          __builtin_prefetch(next_gray + u_begin);
          __builtin_prefetch(next_gray + u_end);
        }
      }
      int u = u_begin;
      for (; u + 4 <= u_end; u += 4) {
        accumulate(with_centroid, depth + u, x_factor + u, y_factor, gray, u, dv, all_lanes);
      }
      if (u == u_end) continue;
      // The last pixels: the four from u with the lanes past the disc masked
      // off, read in place while they lie in the image (a copy of them cost a
      // call to memcpy per row), else from copies padded with NaN depth.
      const v_float32x4& last = first_lanes[u_end - u];
      if (u + 4 <= size.width) {
        accumulate(with_centroid, depth + u, x_factor + u, y_factor, gray, u, dv, last);
      } else {
        float tail_depth[4], tail_x_factor[4] = {};
        std::fill_n(tail_depth, 4, std::numeric_limits<float>::quiet_NaN());
        std::copy(depth + u, depth + u_end, tail_depth);
        std::copy(x_factor + u, x_factor + u_end, tail_x_factor);
        accumulate(with_centroid, tail_depth, tail_x_factor, y_factor, gray, u, dv, last);
      }
    }
  };
  if (with_intensity_centroid) {
    sumDisc(std::true_type{});
  } else {
    sumDisc(std::false_type{});
  }
  if (nb.kept < 3) return std::nullopt;
  const double inv = 1.0 / nb.kept;
  const auto sum = [](const v_float32x4& lanes) -> double { return cv::v_reduce_sum(lanes); };
  const Eigen::Vector3d mean_offset = Eigen::Vector3d(sum(sx), sum(sy), sum(sz)) * inv;
  nb.centroid = nb.point + mean_offset;
  nb.spread << sum(sxx), sum(sxy), sum(sxz), sum(sxy), sum(syy), sum(syz), sum(sxz), sum(syz), sum(szz);
  nb.spread *= inv;
  nb.covariance = nb.spread - mean_offset * mean_offset.transpose();
  // The intensity centroid from ranks, not intensities, so that a monotonic
  // illumination change cannot turn it: sum (rank - mean rank)(q - k).
  // Tied pixels take the middle rank of their run: a run of equal values
  // (a dark area that a cube transform flattened) then weighs as it would had
  // its pixels differed, which keeps the centroid's direction. The mean
  // middle rank is (n - 1) / 2. All pixels of one grey level share a rank,
  // so the sum runs over levels. Twice a middle rank less the mean,
  // 2 below + count - kept, is an integer: the sums are exact in integers.
  if (!with_intensity_centroid) return nb;
  int64_t sum_u = 0, sum_v = 0;
  for (int g = 0, below = 0; g < 256; below += count[g], ++g) {
    const int64_t twice_rank = 2 * below + count[g] - nb.kept;
    const int32_t offset_u = static_cast<int32_t>(static_cast<uint32_t>(offsets[g]));
    const int64_t offset_v = (offsets[g] - offset_u) / (int64_t{1} << 32);
    sum_u += twice_rank * offset_u, sum_v += twice_rank * offset_v;
  }
  nb.intensity_centroid = 0.5 * Eigen::Vector2d(static_cast<double>(sum_u), static_cast<double>(sum_v));
  return nb;
}

float ellipseRadius(const Neighbourhood& nb, const Intrinsics& intrinsics, double min_px, double max_px) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(nb.spread, Eigen::EigenvaluesOnly);
  const double major_semi_axis = 2.0 * std::sqrt(std::max(0.0, solver.eigenvalues()(2)));
  const double focal = 0.5 * (intrinsics.fx + intrinsics.fy);
  const double projected = major_semi_axis * focal / nb.point.z();
  const double upper = std::min<double>(nb.initial_radius_px, max_px);
  return static_cast<float>(std::clamp(projected, std::min(min_px, upper), upper));
}

}  // namespace risas

#include "risas/main_normal.hpp"

#include "point_lanes.hpp"

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace risas {

namespace {

// The sector of the angle acos(c) in [0, pi] cut into n_s sectors: acos is
// decreasing, so it is the number of sector boundaries cos(k pi / n_s),
// k = 1 .. n_s - 1, that c lies below. No acos per pixel.
struct SectorBoundaries {
  std::vector<float> cosines;
  explicit SectorBoundaries(int n_s) {
    for (int k = 1; k < n_s; ++k) cosines.push_back(static_cast<float>(std::cos(k * CV_PI / n_s)));
  }
  int sector(float c) const {
    int label = 0;
    for (float b : cosines) label += c < b;
    return label;
  }
};

cv::Vec3i labelsOf(const cv::Vec3f& normal, const SectorBoundaries& boundaries) {
  return {boundaries.sector(normal[0]), boundaries.sector(normal[1]), boundaries.sector(normal[2])};
}

}  // namespace

cv::Vec3i normalLabels(const cv::Vec3f& normal, int n_s) { return labelsOf(normal, SectorBoundaries(n_s)); }

cv::Vec3f computeMainNormal(const cv::Mat& normals, int n_s) {
  CV_Assert(normals.type() == CV_32FC3 && n_s >= 1);
  const int bins = n_s * n_s * n_s;  // bin `bins`: no normal
  const SectorBoundaries boundaries(n_s);
  // The bin of each normal, four at a time: their x, y and z de-interleaved
  // into lanes, each lane's labels counted by comparisons as labelsOf does.
  using cv::v_float32x4;
  using cv::v_int32x4;
  const auto binsOf = [&](const float* xyz, int* out) {
    v_float32x4 x, y, z;
    cv::v_load_deinterleave(xyz, x, y, z);
    v_int32x4 lx = cv::v_setzero_s32(), ly = lx, lz = lx;
    for (float b : boundaries.cosines) {
      const v_float32x4 boundary = cv::v_setall_f32(b);
      // A true comparison is all ones, -1 as an integer.
      lx -= cv::v_reinterpret_as_s32(x < boundary);
      ly -= cv::v_reinterpret_as_s32(y < boundary);
      lz -= cv::v_reinterpret_as_s32(z < boundary);
    }
    const v_int32x4 n = cv::v_setall_s32(n_s);
    const v_int32x4 bin = (lx * n + ly) * n + lz;
    const v_int32x4 none = cv::v_reinterpret_as_s32(z == cv::v_setzero_f32());
    cv::v_store(out, cv::v_select(none, cv::v_setall_s32(bins), bin));
  };
  // Per normal, reused from frame to frame; rows padded to whole fours.
  const int cols = normals.cols, padded_cols = (cols + 3) / 4 * 4;
  thread_local std::vector<int> bin_of;
  bin_of.resize(static_cast<size_t>(normals.rows) * padded_cols);
  for (int r = 0; r < normals.rows; ++r) {
    int* bin = bin_of.data() + static_cast<size_t>(r) * padded_cols;
    inFours(normals.ptr<cv::Vec3f>(r), cols, cv::Vec3f(0, 0, 0),
            [&](const float* xyz, int c) { binsOf(xyz, bin + c); });
  }
  // Counted in four histograms taking turns: neighbouring normals mostly
  // share a bin, and in one histogram each count would wait for the last.
  constexpr size_t kCopies = 4;
  const size_t copy_size = static_cast<size_t>(bins) + 1;
  std::vector<int> counts(kCopies * copy_size, 0), histogram(copy_size, 0);
  for (size_t i = 0; i < bin_of.size(); ++i) ++counts[i % kCopies * copy_size + static_cast<size_t>(bin_of[i])];
  for (size_t i = 0; i < counts.size(); ++i) histogram[i % copy_size] += counts[i];
  const int mode = static_cast<int>(std::max_element(histogram.begin(), histogram.end() - 1) - histogram.begin());
  if (histogram[static_cast<size_t>(mode)] == 0) return {0.0f, 0.0f, -1.0f};
  // The mean of the mode's normals, four at a time in double lanes, the
  // others masked out: branching on a normal's bin would mispredict.
  using cv::v_float64x2;
  v_float64x2 sx = cv::v_setzero_f64(), sy = sx, sz = sx;
  const auto addModes = [&](const float* xyz, const int* bin) {
    v_float32x4 x, y, z;
    cv::v_load_deinterleave(xyz, x, y, z);
    const v_float32x4 in = cv::v_reinterpret_as_f32(cv::v_load(bin) == cv::v_setall_s32(mode));
    x = x & in, y = y & in, z = z & in;
    sx += cv::v_cvt_f64(x) + cv::v_cvt_f64_high(x);
    sy += cv::v_cvt_f64(y) + cv::v_cvt_f64_high(y);
    sz += cv::v_cvt_f64(z) + cv::v_cvt_f64_high(z);
  };
  for (int r = 0; r < normals.rows; ++r) {
    const int* bin = bin_of.data() + static_cast<size_t>(r) * padded_cols;
    inFours(normals.ptr<cv::Vec3f>(r), cols, cv::Vec3f(0, 0, 0),
            [&](const float* xyz, int c) { addModes(xyz, bin + c); });
  }
  const cv::Vec3d sum(cv::v_reduce_sum(sx), cv::v_reduce_sum(sy), cv::v_reduce_sum(sz));
  const cv::Vec3d mean = cv::normalize(sum);
  return cv::Vec3f(static_cast<float>(mean[0]), static_cast<float>(mean[1]), static_cast<float>(mean[2]));
}

void dotProductImage(const FrameGeometry& geometry, const cv::Vec3f& n_main, double sigma, cv::Mat& P) {
  const cv::Mat& normals = geometry.normals;
  CV_Assert(normals.type() == CV_32FC3);
  // P is smooth (sigma of a few pixels), so it is formed on the normals' own
  // grid, one value per block, filtered with sigma / stride and enlarged
  // bilinearly: the same image at a fraction of the filtering.
  const int stride = geometry.normal_stride;
  // Per-thread buffers, reused from frame to frame (see normals.cpp).
  thread_local cv::Mat p, weight, full;
  p.create(normals.size(), CV_32FC1);
  weight.create(normals.size(), CV_32FC1);
  for (int r = 0; r < normals.rows; ++r) {
    const cv::Vec3f* n = normals.ptr<cv::Vec3f>(r);
    float* pr = p.ptr<float>(r);
    float* wr = weight.ptr<float>(r);
    for (int c = 0; c < normals.cols; ++c) {
      // P and its weight (1 where there is a normal): with the division
      // after smoothing this is a normalised convolution.
      const bool has = n[c][2] != 0.0f;
      pr[c] = has ? 255.0f * std::abs(n_main.dot(n[c])) : 0.0f;
      wr[c] = has ? 1.0f : 0.0f;
    }
  }
  if (sigma > 0.0) {
    cv::GaussianBlur(p, p, cv::Size(), sigma / stride, sigma / stride, cv::BORDER_REPLICATE);
    cv::GaussianBlur(weight, weight, cv::Size(), sigma / stride, sigma / stride, cv::BORDER_REPLICATE);
  }
  // Far inside large holes the weight vanishes; those pixels have no
  // keypoints and no neighbour with one within the Harris window, so 0 is as
  // good as any value there.
  for (int r = 0; r < p.rows; ++r) {
    float* pr = p.ptr<float>(r);
    const float* wr = weight.ptr<float>(r);
    for (int c = 0; c < p.cols; ++c) pr[c] = wr[c] > 1e-3f ? pr[c] / wr[c] : 0.0f;
  }
  const cv::Size size = geometry.size();
  if (p.cols * stride == size.width && p.rows * stride == size.height) {
    cv::resize(p, P, size, 0, 0, cv::INTER_LINEAR);
  } else {  // partial blocks: enlarge to whole blocks, then crop
    cv::resize(p, full, cv::Size(p.cols * stride, p.rows * stride), 0, 0, cv::INTER_LINEAR);
    full(cv::Rect(cv::Point(0, 0), size)).copyTo(P);
  }
}

}  // namespace risas

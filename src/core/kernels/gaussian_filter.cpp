#include "gaussian_filter.hpp"

#include "vector_clones.hpp"
#include "with_default.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <type_traits>

namespace risas {

cv::Size gaussianSize(double sigma) {
  const int k = 2 * cvCeil(3.0 * sigma) + 1;
  return {k, k};
}

std::vector<float> gaussianHalfKernel(double sigma) {
  const cv::Mat kernel = cv::getGaussianKernel(gaussianSize(sigma).width, sigma, CV_32F);
  const int radius = kernel.rows / 2;
  return std::vector<float>(kernel.ptr<float>(radius), kernel.ptr<float>(radius) + radius + 1);
}

// out[u] += weight (before[u] + after[u]): one pair of taps over a row. Its
// own function: inlined, GCC jammed two taps into one loop and left it
// scalar.
RISAS_VECTOR_CLONES
void addTaps(const float* before, const float* after, float weight, int cols, float* __restrict out) {
  for (int u = 0; u < cols; ++u) out[u] += weight * (before[u] + after[u]);
}

// With the default radius a compile-time constant the compiler unrolls the
// taps and vectorises the loop over the outputs as it stands; with a radius
// known only at run time it would not, so that one adds a pair of taps at a
// time over the row, in the same order.
template <class Radius>
RISAS_VECTOR_CLONES
void symmetricWindow(const float* const* taps, const float* half, Radius radius, int cols, float* __restrict out) {
  if constexpr (std::is_integral_v<Radius>) {
    const float* centre = taps[radius];
    for (int u = 0; u < cols; ++u) out[u] = half[0] * centre[u];
    for (int t = 1; t <= radius; ++t) addTaps(taps[radius - t], taps[radius + t], half[t], cols, out);
  } else {
    for (int u = 0; u < cols; ++u) {
      float sum = half[0] * taps[radius][u];
      for (int t = 1; t <= radius; ++t) sum += half[t] * (taps[radius - t][u] + taps[radius + t][u]);
      out[u] = sum;
    }
  }
}

template void symmetricWindow(const float* const*, const float*, int, int, float*);
template void symmetricWindow(const float* const*, const float*, std::integral_constant<int, kDefaultWindowRadius>,
                              int, float*);
template void symmetricWindow(const float* const*, const float*, std::integral_constant<int, kDefaultDotProductRadius>,
                              int, float*);
template void symmetricWindow(const float* const*, const float*, std::integral_constant<int, kDefaultGrayRadius>,
                              int, float*);

void BlurredRows::reset(const cv::Mat& src, const std::vector<float>& half, int border) {
  CV_Assert((src.type() == CV_8UC1 || src.type() == CV_32FC1) && !src.empty() && !half.empty());
  CV_Assert(border == cv::BORDER_REPLICATE || border == cv::BORDER_REFLECT_101);
  src_ = &src, half_ = half, border_ = border;
  const int radius = static_cast<int>(half.size()) - 1, span = 2 * radius + 1;
  padded_.resize(static_cast<size_t>(src.cols + 2 * radius));
  along_taps_.resize(static_cast<size_t>(span));
  for (int t = 0; t < span; ++t) along_taps_[static_cast<size_t>(t)] = padded_.data() + t;
  column_taps_.resize(static_cast<size_t>(span));
  along_.reset(src.cols, span);
  finished_.reset(src.cols, 3);
}

// Row v filtered along: in float, extended by radius columns either side.
void BlurredRows::filterAlong(int v, float* out) {
  const int radius = static_cast<int>(half_.size()) - 1, cols = src_->cols;
  float* row = padded_.data() + radius;
  if (src_->depth() == CV_8U) {
    const uchar* in = src_->ptr<uchar>(v);
    std::copy(in, in + cols, row);
  } else {
    const float* in = src_->ptr<float>(v);
    std::copy(in, in + cols, row);
  }
  for (int t = 1; t <= radius; ++t) {
    row[-t] = row[borderIndex(-t, cols, border_)];
    row[cols - 1 + t] = row[borderIndex(cols - 1 + t, cols, border_)];
  }
  withDefault<kDefaultWindowRadius, kDefaultDotProductRadius, kDefaultGrayRadius>(
      radius, [&](auto fixed_radius) { symmetricWindow(along_taps_.data(), half_.data(), fixed_radius, cols, out); });
}

const float* BlurredRows::row(int v) {
  return finished_.row(v, [&](int, float* out) {
    // Down the columns: the rows at the taps' offsets, extrapolated alike.
    // They are span consecutive rows (reflected or replicated at the
    // edges), all held in along_'s span slots at once.
    const int radius = static_cast<int>(half_.size()) - 1, rows = src_->rows;
    for (int t = 0; t <= 2 * radius; ++t) {
      const int source = borderIndex(v + t - radius, rows, border_);
      column_taps_[static_cast<size_t>(t)] = along_.row(source, [&](int i, float* o) { filterAlong(i, o); });
    }
    withDefault<kDefaultWindowRadius, kDefaultDotProductRadius, kDefaultGrayRadius>(
        radius, [&](auto fixed_radius) {
          symmetricWindow(column_taps_.data(), half_.data(), fixed_radius, src_->cols, out);
        });
  });
}

}  // namespace risas

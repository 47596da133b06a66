#include "gaussian_filter.hpp"

#include "vector_clones.hpp"
#include "with_default.hpp"

#include <opencv2/core/hal/intrin.hpp>
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

// With the default radius a compile-time constant the compiler unrolls the
// taps and vectorises the loop as it stands, sixteen outputs per AVX-512
// register; with a radius known only at run time it would not vectorise it
// at all, so that one is written in four-wide intrinsics, with a scalar tail
// that adds in the lanes' order.
template <class Radius>
RISAS_VECTOR_CLONES
void symmetricWindow(const float* const* taps, const float* half, Radius radius, int cols, float* __restrict out) {
  int u = 0;
  if constexpr (std::is_integral_v<Radius>) {
    for (; u + 4 <= cols; u += 4) {
      cv::v_float32x4 sum = cv::v_setall_f32(half[0]) * cv::v_load(taps[radius] + u);
      for (int t = 1; t <= radius; ++t) {
        sum += cv::v_setall_f32(half[t]) * (cv::v_load(taps[radius - t] + u) + cv::v_load(taps[radius + t] + u));
      }
      cv::v_store(out + u, sum);
    }
  }
  for (; u < cols; ++u) {
    float sum = half[0] * taps[radius][u];
    for (int t = 1; t <= radius; ++t) sum += half[t] * (taps[radius - t][u] + taps[radius + t][u]);
    out[u] = sum;
  }
}

template void symmetricWindow(const float* const*, const float*, int, int, float*);
template void symmetricWindow(const float* const*, const float*, std::integral_constant<int, kDefaultGaussianRadius>,
                              int, float*);

void blurReplicated(const cv::Mat& src, const std::vector<float>& half, cv::Mat& dst) {
  CV_Assert(src.type() == CV_32FC1 && !half.empty() && dst.data != src.data);
  const int radius = static_cast<int>(half.size()) - 1, rows = src.rows, cols = src.cols;
  // Per thread, reused from frame to frame.
  thread_local cv::Mat along;  // filtered along the rows
  thread_local std::vector<float> padded;
  along.create(src.size(), CV_32FC1);
  dst.create(src.size(), CV_32FC1);
  padded.resize(static_cast<size_t>(cols + 2 * radius));
  std::vector<const float*> taps(static_cast<size_t>(2 * radius + 1));
  withDefault<kDefaultGaussianRadius>(radius, [&](auto fixed_radius) {
    for (int v = 0; v < rows; ++v) {
      const float* row = src.ptr<float>(v);
      std::fill_n(padded.begin(), radius, row[0]);
      std::copy(row, row + cols, padded.begin() + radius);
      std::fill_n(padded.begin() + radius + cols, radius, row[cols - 1]);
      for (int t = 0; t <= 2 * radius; ++t) taps[static_cast<size_t>(t)] = padded.data() + t;
      symmetricWindow(taps.data(), half.data(), fixed_radius, cols, along.ptr<float>(v));
    }
    for (int v = 0; v < rows; ++v) {
      for (int t = 0; t <= 2 * radius; ++t) {
        taps[static_cast<size_t>(t)] = along.ptr<float>(std::clamp(v + t - radius, 0, rows - 1));
      }
      symmetricWindow(taps.data(), half.data(), fixed_radius, cols, dst.ptr<float>(v));
    }
  });
}

}  // namespace risas

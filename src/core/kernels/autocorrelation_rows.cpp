// The fast kernel of eq. 1 (risas::autocorrelationResponse, detector.cpp):
// the same response, row by row, with no tensor or gradient image. See
// autocorrelation_rows.hpp for the contract.
#include "autocorrelation_rows.hpp"

#include "risas/workspace.hpp"

#include "enlarged_rows.hpp"
#include "gaussian_filter.hpp"
#include "vector_clones.hpp"
#include "with_default.hpp"

#include <opencv2/core/hal/intrin.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace risas {
namespace {

// Runs stage(rows) over horizontal stripes of an image of `rows` rows, in
// parallel. A filter applied to a stripe (a ROI) reads the rows beyond it
// from the whole image, and the border rule applies only at the image's
// edges, so the stripes give the very image one call would; each stage ends
// before the next begins, so a stage may read all of the previous one.
template <class Stage>
void inStripes(int rows, Stage&& stage) {
  cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& stripe) { stage(stripe); },
                    std::max(1, cv::getNumThreads()));
}

// A row of the Sobel derivatives scaled by 1/8, the central differences of
// a [1 2 1]-smoothed image (grey levels per pixel for both channels alike),
// from the image's rows above, at and below it (the row itself at the
// image's edges), replicated at the row's ends. Written out, unlike
// cv::Sobel, so the tensor entries are formed from the rows without four
// intermediate images.
RISAS_VECTOR_CLONES
void sobelRow(const float* __restrict a0, const float* __restrict a1, const float* __restrict a2, int cols,
              float* __restrict dx, float* __restrict dy) {
  const auto at = [&](int u) {
    const int l = std::max(u - 1, 0), r = std::min(u + 1, cols - 1);
    dx[u] = 0.125f * ((a0[r] - a0[l]) + 2.0f * (a1[r] - a1[l]) + (a2[r] - a2[l]));
    dy[u] = 0.125f * ((a2[l] + 2.0f * a2[u] + a2[r]) - (a0[l] + 2.0f * a0[u] + a0[r]));
  };
  at(0);
  for (int u = 1; u < cols - 1; ++u) {  // the same as at(u), without the clamps: vectorised
    dx[u] = 0.125f * ((a0[u + 1] - a0[u - 1]) + 2.0f * (a1[u + 1] - a1[u - 1]) + (a2[u + 1] - a2[u - 1]));
    dy[u] = 0.125f * ((a2[u - 1] + 2.0f * a2[u] + a2[u + 1]) - (a0[u - 1] + 2.0f * a0[u] + a0[u + 1]));
  }
  if (cols > 1) at(cols - 1);
}

// One row of eq. 1's structure tensor before the window, tau M_I + (1 - tau) M_P.
RISAS_VECTOR_CLONES
void tensorRow(const float* __restrict gx, const float* __restrict gy, const float* __restrict px,
               const float* __restrict py, float tau, int cols, float* __restrict xx, float* __restrict xy,
               float* __restrict yy) {
  const float shape = 1.0f - tau;
  for (int u = 0; u < cols; ++u) {
    xx[u] = tau * gx[u] * gx[u] + shape * px[u] * px[u];
    xy[u] = tau * gx[u] * gy[u] + shape * px[u] * py[u];
    yy[u] = tau * gy[u] * gy[u] + shape * py[u] * py[u];
  }
}

// Harris: R = det(M) - k trace(M)^2. Returns the row's largest R (which
// the threshold needs), taken while the row is at hand.
RISAS_VECTOR_CLONES
float harrisRow(const float* __restrict xx, const float* __restrict xy, const float* __restrict yy, float k, int cols,
                float* __restrict r) {
  for (int u = 0; u < cols; ++u) r[u] = xx[u] * yy[u] - xy[u] * xy[u] - k * (xx[u] + yy[u]) * (xx[u] + yy[u]);
  // In lanes: a scalar max would keep the compiler from vectorising (NaN order).
  cv::v_float32x4 lanes = cv::v_setall_f32(-std::numeric_limits<float>::infinity());
  int u = 0;
  for (; u + 4 <= cols; u += 4) lanes = cv::v_max(lanes, cv::v_load(r + u));
  float largest = cv::v_reduce_max(lanes);
  for (; u < cols; ++u) largest = std::max(largest, r[u]);
  return largest;
}

// One thread's rows for the window stage (see computeResponse): rows an odd
// number of cache lines apart, starting on a line, so that the filters'
// vector loads of a whole row's columns do not straddle lines. (An odd
// number: rows a multiple of 4 KiB apart made the CPU take each row's loads
// for reads of the stores just made to another row, 4K aliasing, and stall
// on them; odd multiples of 64 bytes never meet a 4 KiB multiple within 64
// rows.)
struct WindowRows {
  static constexpr int kGradients = 4, kTensor = 3;  // gx, gy, px, py; xx, xy, yy
  static constexpr size_t kLineFloats = 64 / sizeof(float);
  std::vector<float> data;
  float* base = nullptr;  // data's first cache-line boundary
  size_t pitch = 0;
  int span = 0;  // rows of the window, 2 radius + 1
  void reset(int cols, int radius) {
    const size_t lines = (static_cast<size_t>(cols + 2 * radius) + kLineFloats - 1) / kLineFloats + 1;
    pitch = (lines | 1) * kLineFloats;
    span = 2 * radius + 1;
    data.resize(pitch * static_cast<size_t>(kGradients + kTensor + kTensor * span + kTensor) + kLineFloats);
    base = data.data();
    while (reinterpret_cast<uintptr_t>(base) % 64) ++base;
  }
  float* row(int i) { return base + static_cast<size_t>(i) * pitch; }
  float* gradient(int i) { return row(i); }
  float* tensor(int entry) { return row(kGradients + entry); }  // with room for the border
  // Entry e of the filtered tensor row r, kept while the window reaches it.
  float* ring(int entry, int r) { return row(kGradients + kTensor + entry * span + (r % span + span) % span); }
  float* window(int entry) { return row(kGradients + kTensor + kTensor * span + entry); }
};

// One thread's rows of a stripe: the window's, and I_grayscale's and I_dp's.
struct StripeBuffers {
  WindowRows window;
  BlurredRows gray;
  EnlargedRows dp;
};

}  // namespace

float autocorrelationRows(const cv::Mat& gray, const std::vector<float>& gray_half, const cv::Mat& P_grid,
                          int normal_stride, const std::vector<float>& window_half, float tau, float k, cv::Mat& R) {
  const cv::Size size = gray.size();
  R.create(size, CV_32FC1);
  // I_grayscale: the grey image blurred with gray_sigma, in float, filtered
  // straight from the 8-bit image (gray_sigma 0: the kernel is [1]), its
  // border reflected as cv::GaussianBlur's, and I_dp, enlarged from its grid:
  // both made a few rows at a time as the pass below reaches them
  // (BlurredRows, EnlargedRows), each thread its own. A tensor row is formed
  // from their gradient rows, filtered along the row and kept in a ring while
  // the column filter's window reaches it; then Harris.
  const std::vector<float>& half = window_half;
  const int window_radius = static_cast<int>(half.size()) - 1, cols = size.width;
  std::vector<float> row_max(static_cast<size_t>(size.height));
  withDefault<kDefaultWindowRadius>(window_radius, [&](auto radius) {
    inStripes(size.height, [&](const cv::Range& rows) {
      StripeBuffers& stripe = Workspace::ofThisThread().get<StripeBuffers>();
      WindowRows& w = stripe.window;
      w.reset(cols, radius);
      BlurredRows& I = stripe.gray;
      I.reset(gray, gray_half, cv::BORDER_REFLECT_101);
      EnlargedRows& P = stripe.dp;
      P.reset(P_grid, normal_stride, size);
      std::vector<const float*> shifted(static_cast<size_t>(w.span)), column(static_cast<size_t>(w.span));
      // Tensor row r (reflected into the image), filtered along the row,
      // into the ring.
      const auto addRow = [&](int r) {
        const int v = borderIndex(r, size.height, cv::BORDER_REFLECT_101);
        const int above = std::max(v - 1, 0), below = std::min(v + 1, size.height - 1);
        sobelRow(I.row(above), I.row(v), I.row(below), cols, w.gradient(0), w.gradient(1));
        sobelRow(P.row(above), P.row(v), P.row(below), cols, w.gradient(2), w.gradient(3));
        tensorRow(w.gradient(0), w.gradient(1), w.gradient(2), w.gradient(3), tau, cols, w.tensor(0) + radius,
                  w.tensor(1) + radius, w.tensor(2) + radius);
        for (int e = 0; e < WindowRows::kTensor; ++e) {
          float* row = w.tensor(e) + radius;
          for (int t = 1; t <= radius; ++t) {
            row[-t] = row[borderIndex(-t, cols, cv::BORDER_REFLECT_101)];
            row[cols - 1 + t] = row[borderIndex(cols - 1 + t, cols, cv::BORDER_REFLECT_101)];
          }
          for (int t = 0; t < w.span; ++t) shifted[static_cast<size_t>(t)] = row + t - radius;
          symmetricWindow(shifted.data(), half.data(), radius, cols, w.ring(e, r));
        }
      };
      for (int r = rows.start - radius; r < rows.start + radius; ++r) addRow(r);
      for (int v = rows.start; v < rows.end; ++v) {
        addRow(v + radius);
        for (int e = 0; e < WindowRows::kTensor; ++e) {
          for (int t = 0; t < w.span; ++t) column[static_cast<size_t>(t)] = w.ring(e, v - radius + t);
          symmetricWindow(column.data(), half.data(), radius, cols, w.window(e));
        }
        row_max[static_cast<size_t>(v)] = harrisRow(w.window(0), w.window(1), w.window(2), k, cols, R.ptr<float>(v));
      }
    });
  });
  return *std::max_element(row_max.begin(), row_max.end());
}

}  // namespace risas

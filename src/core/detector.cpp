#include "risas/detector.hpp"

#include "risas/errors.hpp"
#include "risas/main_normal.hpp"

#include "enlarged_rows.hpp"
#include "gaussian_filter.hpp"
#include "marked_columns.hpp"
#include "vector_clones.hpp"
#include "with_default.hpp"

#include <opencv2/core/hal/intrin.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace risas {
namespace {

// The images one frame's response keeps whole, the dot-product grid and R,
// one set per thread and reused from frame to frame: allocated afresh per
// frame, images cost more in page faults than the filtering. (The grey and
// dot-product images are made a few rows at a time, see computeResponse.)
struct ResponseBuffers {
  cv::Mat P_grid, R;
};

ResponseBuffers& buffers() {
  thread_local ResponseBuffers b;
  return b;
}

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

// Row v's candidates for a local maximum (1, else 0): above the threshold and
// not below any 4-neighbour, which no maximum of a larger window is. up and
// down are rows v - 1 and v + 1 (the row itself at the image's edges); the
// first and last columns, which lack a side neighbour, are candidates when
// above the threshold.
RISAS_VECTOR_CLONES
void candidateRow(const float* __restrict up, const float* __restrict row, const float* __restrict down,
                  float threshold, int cols, uchar* __restrict candidate) {
  for (int u = 1; u < cols - 1; ++u) {  // vectorised
    const float c = row[u];
    candidate[u] = (c > threshold) & (c >= row[u - 1]) & (c >= row[u + 1]) & (c >= up[u]) & (c >= down[u]);
  }
  candidate[0] = row[0] > threshold;
  candidate[cols - 1] = row[cols - 1] > threshold;
}

}  // namespace

Detector::Detector(const DetectorParams& params) : params_(params) {
  params_.validate();
  gray_half_ = gaussianHalfKernel(params_.gray_sigma);
  window_half_ = gaussianHalfKernel(params_.window_sigma);
}

float Detector::computeResponse(const RgbdFrame& frame, const FrameGeometry& geometry, cv::Mat& R) const {
  if (!geometry.fits(frame.size())) throw InputError("geometry does not belong to this frame");
  ResponseBuffers& b = buffers();
  const float tau = static_cast<float>(params_.tau);
  const float k = static_cast<float>(params_.harris_k);
  const cv::Size size = frame.size();
  R.create(size, CV_32FC1);

  const cv::Vec3f n_main = computeMainNormal(geometry.normals, params_.n_s);
  // P on the normals' grid, enlarged row by row as the pass below reaches
  // the rows (EnlargedRows), each thread its own.
  dotProductGrid(geometry, n_main, params_.dp_sigma, b.P_grid);
  // I: the grey image blurred with gray_sigma, in float, filtered straight
  // from the 8-bit image (gray_sigma 0: the kernel is [1]), its border
  // reflected as cv::GaussianBlur's. Its rows are made as the pass below
  // reaches them (BlurredRows), each thread its own.
  // Eq. 1: E(u,v) = sum w [tau dI^2 + (1 - tau) dP^2], whose second-order
  // expansion is the structure tensor M = tau M_I + (1 - tau) M_P; then the
  // window w (cv::GaussianBlur's kernel and reflected border), then Harris.
  // Row by row, with no tensor image: a tensor row is formed from the grey
  // and P rows, filtered along the row and kept in a ring while the column
  // filter's window reaches it.
  const std::vector<float>& half = window_half_;
  const int window_radius = static_cast<int>(half.size()) - 1, cols = size.width;
  std::vector<float> row_max(static_cast<size_t>(size.height));
  withDefault<kDefaultWindowRadius>(window_radius, [&](auto radius) {
    inStripes(size.height, [&](const cv::Range& rows) {
      thread_local WindowRows w;
      w.reset(cols, radius);
      thread_local BlurredRows I;
      I.reset(frame.gray(), gray_half_, cv::BORDER_REFLECT_101);
      thread_local EnlargedRows P;
      P.reset(b.P_grid, geometry.normal_stride, size);
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

cv::Mat Detector::response(const RgbdFrame& frame, const FrameGeometry& geometry) const {
  cv::Mat R;
  computeResponse(frame, geometry, R);
  return R;
}

void Detector::detect(const RgbdFrame& frame, const FrameGeometry& geometry, std::vector<cv::KeyPoint>& keypoints,
                      const cv::Mat& mask) const {
  keypoints.clear();
  if (!mask.empty() && (mask.size() != frame.size() || mask.type() != CV_8UC1)) {
    throw InputError("detection mask must be CV_8UC1 of the frame's size");
  }
  ResponseBuffers& buffer = buffers();
  const float max_response = computeResponse(frame, geometry, buffer.R);
  const cv::Mat& R = buffer.R;
  if (!(max_response > 0.0f)) return;
  const float threshold = static_cast<float>(params_.response_threshold * max_response);

  // Non-maximum suppression: a keypoint is the largest response of its
  // (2 nms_radius + 1)^2 neighbourhood. Tested in full only at candidates
  // (candidateRow), found a whole row at a time: most pixels fail there,
  // without a full-frame maximum filter.
  const int radius = params_.nms_radius;
  const auto isLocalMaximum = [&](int v, int u, float value) {
    for (int dv = std::max(-radius, -v); dv <= std::min(radius, R.rows - 1 - v); ++dv) {
      const float* row = R.ptr<float>(v + dv);
      for (int du = std::max(-radius, -u); du <= std::min(radius, R.cols - 1 - u); ++du) {
        if (row[u + du] > value) return false;
      }
    }
    return true;
  };
  const int b = params_.border, u_end = R.cols - b;
  thread_local std::vector<uchar> candidates;
  candidates.assign(static_cast<size_t>(R.cols) + 8, 0);  // room to read whole eights
  for (int v = b; v < R.rows - b; ++v) {
    const float* r = R.ptr<float>(v);
    candidateRow(R.ptr<float>(std::max(v - 1, 0)), r, R.ptr<float>(std::min(v + 1, R.rows - 1)), threshold,
                 R.cols, candidates.data());
    const uchar* allowed = mask.empty() ? nullptr : mask.ptr<uchar>(v);
    forEachMarked(candidates.data(), b, u_end, [&](int u) {
      if (!isLocalMaximum(v, u, r[u])) return;
      if ((allowed && !allowed[u]) || !geometry.hasNormal(v, u)) return;
      keypoints.emplace_back(cv::Point2f(static_cast<float>(u), static_cast<float>(v)),
                             static_cast<float>(6.0 * params_.window_sigma), -1.0f, r[u]);
    });
  }
  retainBestSpread(keypoints, params_.max_keypoints, frame.size(), params_.grid_cols, params_.grid_rows);
}

void retainBestSpread(std::vector<cv::KeyPoint>& keypoints, int max_count, cv::Size image_size, int grid_cols,
                      int grid_rows) {
  std::stable_sort(keypoints.begin(), keypoints.end(),
                   [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  if (static_cast<int>(keypoints.size()) <= max_count) return;

  const int cells = grid_cols * grid_rows;
  const int share = (max_count + cells - 1) / cells;
  std::vector<int> taken_in_cell(static_cast<size_t>(cells), 0);
  std::vector<char> taken(keypoints.size(), 0);
  int total = 0;
  for (size_t i = 0; i < keypoints.size() && total < max_count; ++i) {
    const int col = std::min(grid_cols - 1, static_cast<int>(keypoints[i].pt.x * grid_cols / image_size.width));
    const int row = std::min(grid_rows - 1, static_cast<int>(keypoints[i].pt.y * grid_rows / image_size.height));
    int& count = taken_in_cell[static_cast<size_t>(row * grid_cols + col)];
    if (count < share) {
      ++count;
      taken[i] = 1;
      ++total;
    }
  }
  for (size_t i = 0; i < keypoints.size() && total < max_count; ++i) {
    if (!taken[i]) {
      taken[i] = 1;
      ++total;
    }
  }
  std::vector<cv::KeyPoint> kept;
  kept.reserve(static_cast<size_t>(max_count));
  for (size_t i = 0; i < keypoints.size(); ++i) {
    if (taken[i]) kept.push_back(keypoints[i]);
  }
  keypoints.swap(kept);
}

}  // namespace risas

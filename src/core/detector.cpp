#include "risas/detector.hpp"

#include "risas/errors.hpp"
#include "risas/main_normal.hpp"

#include "vector_clones.hpp"

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <limits>
#include <vector>

namespace risas {
namespace {

// The images one frame's response passes through, one set per thread and
// reused from frame to frame: a VGA frame needs about 20 MB of them, which
// allocated afresh per frame cost more in page faults than the filtering.
struct ResponseBuffers {
  cv::Mat raw, I, P, R;
  cv::Mat tensor[3], window[3];  // the entries xx, xy, yy of eq. 1's structure tensor, one plane each
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

// The Gaussian kernel truncated at 3 sigma, as OpenCV itself does for 8-bit
// images (its float default, 4 sigma, adds taps of < 0.3 % of the weight).
cv::Size gaussianSize(double sigma) {
  const int k = 2 * cvCeil(3.0 * sigma) + 1;
  return {k, k};
}

// Row v of the Sobel derivatives scaled by 1/8, the central differences of a
// [1 2 1]-smoothed image (grey levels per pixel for both channels alike),
// replicated at the edges. Written out, unlike cv::Sobel, so the tensor
// entries are formed from the rows without four intermediate images.
RISAS_VECTOR_CLONES void sobelRow(const cv::Mat& image, int v, float* __restrict dx, float* __restrict dy) {
  const int cols = image.cols;
  const float* __restrict a0 = image.ptr<float>(std::max(v - 1, 0));
  const float* __restrict a1 = image.ptr<float>(v);
  const float* __restrict a2 = image.ptr<float>(std::min(v + 1, image.rows - 1));
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
RISAS_VECTOR_CLONES void tensorRow(const float* __restrict gx, const float* __restrict gy, const float* __restrict px,
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
RISAS_VECTOR_CLONES float harrisRow(const float* __restrict xx, const float* __restrict xy, const float* __restrict yy, float k, int cols,
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

}  // namespace

Detector::Detector(const DetectorParams& params) : params_(params) { params_.validate(); }

float Detector::computeResponse(const RgbdFrame& frame, const FrameGeometry& geometry, cv::Mat& R) const {
  if (geometry.size() != frame.size()) throw InputError("geometry does not belong to this frame");
  ResponseBuffers& b = buffers();
  const float tau = static_cast<float>(params_.tau);
  const float k = static_cast<float>(params_.harris_k);
  const double gray_sigma = params_.gray_sigma, window_sigma = params_.window_sigma;
  const cv::Size size = frame.size();
  for (cv::Mat* image : {&b.raw, &b.I, &b.tensor[0], &b.tensor[1], &b.tensor[2], &b.window[0], &b.window[1],
                         &b.window[2], &R}) {
    image->create(size, CV_32FC1);
  }

  const cv::Vec3f n_main = computeMainNormal(geometry.normals, params_.n_s);
  dotProductImage(geometry, n_main, params_.dp_sigma, b.P);
  inStripes(size.height, [&](const cv::Range& rows) {
    frame.gray().rowRange(rows).convertTo(b.raw.rowRange(rows), CV_32F);
  });
  inStripes(size.height, [&](const cv::Range& rows) {
    if (gray_sigma > 0) {
      cv::GaussianBlur(b.raw.rowRange(rows), b.I.rowRange(rows), gaussianSize(gray_sigma), gray_sigma, gray_sigma);
    } else {
      b.raw.rowRange(rows).copyTo(b.I.rowRange(rows));
    }
  });
  // Eq. 1: E(u,v) = sum w [tau dI^2 + (1 - tau) dP^2], whose second-order
  // expansion is the structure tensor M = tau M_I + (1 - tau) M_P.
  inStripes(size.height, [&](const cv::Range& rows) {
    thread_local std::vector<float> gradient_rows;
    gradient_rows.resize(4 * static_cast<size_t>(size.width));
    float* gx = gradient_rows.data();
    float *gy = gx + size.width, *px = gy + size.width, *py = px + size.width;
    for (int v = rows.start; v < rows.end; ++v) {
      sobelRow(b.I, v, gx, gy);
      sobelRow(b.P, v, px, py);
      tensorRow(gx, gy, px, py, tau, size.width, b.tensor[0].ptr<float>(v), b.tensor[1].ptr<float>(v),
                b.tensor[2].ptr<float>(v));
    }
  });
  // The window w, then Harris.
  std::vector<float> row_max(static_cast<size_t>(size.height));
  inStripes(size.height, [&](const cv::Range& rows) {
    for (int i = 0; i < 3; ++i) {
      cv::GaussianBlur(b.tensor[i].rowRange(rows), b.window[i].rowRange(rows), gaussianSize(window_sigma), window_sigma,
                       window_sigma);
    }
    for (int v = rows.start; v < rows.end; ++v) {
      row_max[static_cast<size_t>(v)] = harrisRow(b.window[0].ptr<float>(v), b.window[1].ptr<float>(v),
                                                  b.window[2].ptr<float>(v), k, size.width, R.ptr<float>(v));
    }
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
  // (2 nms_radius + 1)^2 neighbourhood. Tested where the response clears the
  // threshold only, the row's two neighbours first: most pixels fail there,
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
  const int b = params_.border;
  for (int v = b; v < R.rows - b; ++v) {
    const float* r = R.ptr<float>(v);
    const uchar* allowed = mask.empty() ? nullptr : mask.ptr<uchar>(v);
    for (int u = b; u < R.cols - b; ++u) {
      if (r[u] <= threshold || (u > 0 && r[u - 1] > r[u]) || (u + 1 < R.cols && r[u + 1] > r[u])) continue;
      if (!isLocalMaximum(v, u, r[u])) continue;
      if ((allowed && !allowed[u]) || !geometry.hasNormal(v, u)) continue;
      keypoints.emplace_back(cv::Point2f(static_cast<float>(u), static_cast<float>(v)),
                             static_cast<float>(6.0 * params_.window_sigma), -1.0f, r[u]);
    }
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

#include "risas/detector.hpp"

#include "risas/errors.hpp"
#include "risas/main_normal.hpp"
#include "risas/workspace.hpp"

#include "kernels/autocorrelation_rows.hpp"
#include "kernels/gaussian_filter.hpp"
#include "kernels/marked_columns.hpp"
#include "kernels/vector_clones.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <vector>

namespace risas {
namespace {

// The images one frame's response keeps whole, the dot-product grid and R,
// one set per thread and reused from frame to frame: allocated afresh per
// frame, images cost more in page faults than the filtering. (The kernel makes
// the grey and dot-product images a few rows at a time.)
struct ResponseBuffers {
  cv::Mat P_grid, R;
};

// The NMS's candidate flags of a row (candidateRow).
struct NmsCandidates {
  std::vector<uchar> flags;
};

ResponseBuffers& buffers() { return Workspace::ofThisThread().get<ResponseBuffers>(); }

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

cv::Mat autocorrelationResponse(const cv::Mat& I_grayscale, const cv::Mat& I_dp, const DetectorParams& params) {
  const double tau = params.tau, k = params.harris_k;
  // The gradients: Sobel, scaled to grey levels per pixel.
  cv::Mat Ix, Iy, Px, Py;
  cv::Sobel(I_grayscale, Ix, CV_32F, 1, 0, 3, 1.0 / 8, 0, cv::BORDER_REPLICATE);
  cv::Sobel(I_grayscale, Iy, CV_32F, 0, 1, 3, 1.0 / 8, 0, cv::BORDER_REPLICATE);
  cv::Sobel(I_dp, Px, CV_32F, 1, 0, 3, 1.0 / 8, 0, cv::BORDER_REPLICATE);
  cv::Sobel(I_dp, Py, CV_32F, 0, 1, 3, 1.0 / 8, 0, cv::BORDER_REPLICATE);
  // M = w * [tau grad I grad I^T + (1 - tau) grad I_dp grad I_dp^T].
  cv::Mat M_xx = tau * Ix.mul(Ix) + (1 - tau) * Px.mul(Px);
  cv::Mat M_xy = tau * Ix.mul(Iy) + (1 - tau) * Px.mul(Py);
  cv::Mat M_yy = tau * Iy.mul(Iy) + (1 - tau) * Py.mul(Py);
  for (cv::Mat* m : {&M_xx, &M_xy, &M_yy}) cv::GaussianBlur(*m, *m, gaussianSize(params.window_sigma), params.window_sigma);
  // Harris: det(M) - k trace(M)^2.
  const cv::Mat trace = M_xx + M_yy;
  return M_xx.mul(M_yy) - M_xy.mul(M_xy) - k * trace.mul(trace);
}

float Detector::computeResponse(const RgbdFrame& frame, const FrameGeometry& geometry, cv::Mat& R) const {
  if (!geometry.fits(frame.size())) throw InputError("geometry does not belong to this frame");
  const cv::Vec3f n_main = computeMainNormal(geometry.normals, params_.n_s);
  if (!cv::useOptimized()) {  // as OpenCV's: cv::setUseOptimized(false) selects the readable path
    cv::Mat I_grayscale, I_dp;
    frame.gray().convertTo(I_grayscale, CV_32F);
    cv::GaussianBlur(I_grayscale, I_grayscale, gaussianSize(params_.gray_sigma), params_.gray_sigma);
    dotProductImage(geometry, n_main, params_.dp_sigma, I_dp);
    R = autocorrelationResponse(I_grayscale, I_dp, params_);
    double largest = 0.0;
    cv::minMaxLoc(R, nullptr, &largest);
    return static_cast<float>(largest);
  }
  // I_dp on the normals' grid; the kernel enlarges it row by row.
  ResponseBuffers& b = buffers();
  dotProductGrid(geometry, n_main, params_.dp_sigma, b.P_grid);
  return autocorrelationRows(frame.gray(), gray_half_, b.P_grid, geometry.normal_stride, window_half_,
                             static_cast<float>(params_.tau), static_cast<float>(params_.harris_k), R);
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
  std::vector<uchar>& candidates = Workspace::ofThisThread().get<NmsCandidates>().flags;
  candidates.assign(static_cast<size_t>(R.cols) + 8, 0);  // room to read whole eights
  // Every local maximum above `threshold`, into keypoints.
  const auto collectMaxima = [&](float threshold) {
    keypoints.clear();
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
  };
  collectMaxima(static_cast<float>(params_.response_threshold * max_response));
  if (static_cast<int>(keypoints.size()) >= params_.min_keypoints) {
    retainBestSpread(keypoints, params_.max_keypoints, frame.size(), params_.grid_cols, params_.grid_rows);
    return;
  }
  // Too few: the strongest maxima anywhere. Not a share per grid cell: below
  // the threshold a texture-poor frame's cells hold little but noise. Above
  // kRoundingFloor only: R ~ (gradient)^4, and 1e-6 is a corner of gradients
  // 0.03 grey levels per pixel, finer than an 8-bit image holds; below it
  // are a flat face's float rounding errors (1e-19 to 1e-8 on a rendered one).
  constexpr float kRoundingFloor = 1e-6f;
  collectMaxima(kRoundingFloor);
  retainBestSpread(keypoints, std::min(params_.min_keypoints, params_.max_keypoints), frame.size(), 1, 1);
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

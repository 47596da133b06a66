#include "risas/detector.hpp"

#include "risas/errors.hpp"
#include "risas/main_normal.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <numeric>

namespace risas {
namespace {

// The images one frame's response passes through, one set per thread and
// reused from frame to frame: a VGA frame needs about 20 MB of them, which
// allocated afresh per frame cost more in page faults than the filtering.
struct ResponseBuffers {
  cv::Mat I, P, gx, gy, px, py, tensor, R, local_max;
};

ResponseBuffers& buffers() {
  thread_local ResponseBuffers b;
  return b;
}

// Sobel scaled by 1/8 is the central difference of a [1 2 1]-smoothed image:
// gradients in grey levels per pixel for both channels alike.
void gradients(const cv::Mat& image, cv::Mat& dx, cv::Mat& dy) {
  cv::Sobel(image, dx, CV_32F, 1, 0, 3, 1.0 / 8.0, 0.0, cv::BORDER_REPLICATE);
  cv::Sobel(image, dy, CV_32F, 0, 1, 3, 1.0 / 8.0, 0.0, cv::BORDER_REPLICATE);
}

}  // namespace

Detector::Detector(const DetectorParams& params) : params_(params) { params_.validate(); }

void Detector::computeResponse(const RgbdFrame& frame, const FrameGeometry& geometry, cv::Mat& R) const {
  if (geometry.points.size() != frame.size()) throw InputError("geometry does not belong to this frame");
  ResponseBuffers& b = buffers();
  const float tau = static_cast<float>(params_.tau);

  frame.gray().convertTo(b.I, CV_32F);
  if (params_.gray_sigma > 0) cv::GaussianBlur(b.I, b.I, cv::Size(), params_.gray_sigma, params_.gray_sigma);
  const cv::Vec3f n_main = computeMainNormal(geometry.normals, params_.n_s);
  dotProductImage(geometry, n_main, params_.dp_sigma, b.P);

  // Eq. 1: E(u,v) = sum w [tau dI^2 + (1 - tau) dP^2], whose second-order
  // expansion is the structure tensor M = tau M_I + (1 - tau) M_P: its three
  // entries before the window w, as one 3-channel image smoothed in one go.
  gradients(b.I, b.gx, b.gy);
  gradients(b.P, b.px, b.py);
  b.tensor.create(frame.size(), CV_32FC3);
  for (int v = 0; v < b.tensor.rows; ++v) {
    const float *gx = b.gx.ptr<float>(v), *gy = b.gy.ptr<float>(v);
    const float *px = b.px.ptr<float>(v), *py = b.py.ptr<float>(v);
    float* t = b.tensor.ptr<float>(v);
    for (int u = 0; u < b.tensor.cols; ++u) {
      t[3 * u] = tau * gx[u] * gx[u] + (1.0f - tau) * px[u] * px[u];
      t[3 * u + 1] = tau * gx[u] * gy[u] + (1.0f - tau) * px[u] * py[u];
      t[3 * u + 2] = tau * gy[u] * gy[u] + (1.0f - tau) * py[u] * py[u];
    }
  }
  const double s = params_.window_sigma;
  cv::GaussianBlur(b.tensor, b.tensor, cv::Size(), s, s);

  // Harris: R = det(M) - k trace(M)^2.
  const float k = static_cast<float>(params_.harris_k);
  R.create(frame.size(), CV_32FC1);
  for (int v = 0; v < R.rows; ++v) {
    const float* t = b.tensor.ptr<float>(v);
    float* r = R.ptr<float>(v);
    for (int u = 0; u < R.cols; ++u) {
      const float a = t[3 * u], c = t[3 * u + 1], d = t[3 * u + 2];
      r[u] = a * d - c * c - k * (a + d) * (a + d);
    }
  }
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
  computeResponse(frame, geometry, buffer.R);
  const cv::Mat& R = buffer.R;

  // Non-maximum suppression: a keypoint is the largest response of its
  // (2 nms_radius + 1)^2 neighbourhood.
  const int w = 2 * params_.nms_radius + 1;
  cv::Mat& local_max = buffer.local_max;
  cv::dilate(R, local_max, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(w, w)));
  double max_response = 0.0;
  cv::minMaxLoc(R, nullptr, &max_response);
  if (max_response <= 0.0) return;
  const float threshold = static_cast<float>(params_.response_threshold * max_response);

  const int b = params_.border;
  for (int v = b; v < R.rows - b; ++v) {
    const float* r = R.ptr<float>(v);
    const float* m = local_max.ptr<float>(v);
    const uchar* allowed = mask.empty() ? nullptr : mask.ptr<uchar>(v);
    for (int u = b; u < R.cols - b; ++u) {
      if (r[u] <= threshold || r[u] < m[u]) continue;
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

#include "risas/main_normal.hpp"

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
  const auto index = [n_s](const cv::Vec3i& l) { return (l[0] * n_s + l[1]) * n_s + l[2]; };
  std::vector<int> histogram(static_cast<size_t>(n_s * n_s * n_s), 0);
  std::vector<cv::Vec3d> sums(histogram.size(), cv::Vec3d(0, 0, 0));
  const SectorBoundaries boundaries(n_s);
  for (int r = 0; r < normals.rows; ++r) {
    const cv::Vec3f* n = normals.ptr<cv::Vec3f>(r);
    for (int c = 0; c < normals.cols; ++c) {
      if (n[c][2] == 0.0f) continue;  // no normal
      const int bin = index(labelsOf(n[c], boundaries));
      ++histogram[bin];
      sums[bin] += cv::Vec3d(n[c][0], n[c][1], n[c][2]);
    }
  }
  const auto mode = std::max_element(histogram.begin(), histogram.end()) - histogram.begin();
  if (histogram[mode] == 0) return {0.0f, 0.0f, -1.0f};
  const cv::Vec3d mean = cv::normalize(sums[mode]);
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
  const cv::Size size = geometry.points.size();
  if (p.cols * stride == size.width && p.rows * stride == size.height) {
    cv::resize(p, P, size, 0, 0, cv::INTER_LINEAR);
  } else {  // partial blocks: enlarge to whole blocks, then crop
    cv::resize(p, full, cv::Size(p.cols * stride, p.rows * stride), 0, 0, cv::INTER_LINEAR);
    full(cv::Rect(cv::Point(0, 0), size)).copyTo(P);
  }
}

}  // namespace risas

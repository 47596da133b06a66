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
  // Every second pixel of every second row: the normals are fitted on a grid
  // at least that coarse (GeometryParams::normal_stride), so the full image
  // would count each fit four times over and change nothing but the time.
  for (int r = 0; r < normals.rows; r += 2) {
    const cv::Vec3f* n = normals.ptr<cv::Vec3f>(r);
    for (int c = 0; c < normals.cols; c += 2) {
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

void dotProductImage(const cv::Mat& normals, const cv::Vec3f& n_main, double sigma, cv::Mat& P) {
  CV_Assert(normals.type() == CV_32FC3);
  // P is smooth (sigma of a few pixels) and the normals come from a grid of
  // every second pixel, so P is formed at half resolution, one value per
  // 2x2 block (the block's mean), filtered with sigma / 2 and enlarged
  // bilinearly: the same image at a quarter of the filtering.
  const int half_rows = (normals.rows + 1) / 2, half_cols = (normals.cols + 1) / 2;
  // Per-thread buffers, reused from frame to frame (see normals.cpp).
  thread_local cv::Mat p, weight, full;
  p.create(half_rows, half_cols, CV_32FC1);
  weight.create(half_rows, half_cols, CV_32FC1);
  for (int r = 0; r < half_rows; ++r) {
    const cv::Vec3f* rows[2] = {normals.ptr<cv::Vec3f>(2 * r), normals.ptr<cv::Vec3f>(std::min(2 * r + 1, normals.rows - 1))};
    float* pr = p.ptr<float>(r);
    float* wr = weight.ptr<float>(r);
    for (int c = 0; c < half_cols; ++c) {
      float sum = 0.0f, count = 0.0f;
      for (const cv::Vec3f* n : rows) {
        for (int cc = 2 * c; cc <= std::min(2 * c + 1, normals.cols - 1); ++cc) {
          if (n[cc][2] == 0.0f) continue;  // no normal
          sum += 255.0f * std::abs(n_main.dot(n[cc]));
          count += 1.0f;
        }
      }
      // Summed P and its weight: with the division after smoothing this is
      // a normalised convolution.
      pr[c] = sum * 0.25f;
      wr[c] = count * 0.25f;
    }
  }
  if (sigma > 0.0) {
    cv::GaussianBlur(p, p, cv::Size(), 0.5 * sigma, 0.5 * sigma, cv::BORDER_REPLICATE);
    cv::GaussianBlur(weight, weight, cv::Size(), 0.5 * sigma, 0.5 * sigma, cv::BORDER_REPLICATE);
  }
  // Far inside large holes the weight vanishes; those pixels have no
  // keypoints and no neighbour with one within the Harris window, so 0 is as
  // good as any value there.
  for (int r = 0; r < half_rows; ++r) {
    float* pr = p.ptr<float>(r);
    const float* wr = weight.ptr<float>(r);
    for (int c = 0; c < half_cols; ++c) pr[c] = wr[c] > 1e-3f ? pr[c] / wr[c] : 0.0f;
  }
  if (half_cols * 2 == normals.cols && half_rows * 2 == normals.rows) {
    cv::resize(p, P, normals.size(), 0, 0, cv::INTER_LINEAR);
  } else {  // odd sizes: enlarge to even, then crop
    cv::resize(p, full, cv::Size(half_cols * 2, half_rows * 2), 0, 0, cv::INTER_LINEAR);
    full(cv::Rect(0, 0, normals.cols, normals.rows)).copyTo(P);
  }
}

}  // namespace risas

#include "risas/main_normal.hpp"

#include "risas/workspace.hpp"

#include "kernels/enlarged_rows.hpp"
#include "kernels/gaussian_filter.hpp"
#include "kernels/vector_clones.hpp"
#include "kernels/with_default.hpp"


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

// The bin of each of a row's normals, (x sector n_s + y sector) n_s +
// z sector as labelsOf gives them, or n_s^3 where there is no normal. N_s is
// an int or, for the default, a compile-time constant (withDefault): the
// loop over the boundaries then unrolls and the loop over normals vectorises.
template <class N_s>
RISAS_VECTOR_CLONES
void binRow(const float* __restrict xyz, int cols, const float* __restrict cosines, N_s n_s, int* __restrict bin) {
  for (int c = 0; c < cols; ++c) {
    const float x = xyz[3 * c], y = xyz[3 * c + 1], z = xyz[3 * c + 2];
    int lx = 0, ly = 0, lz = 0;
    for (int k = 0; k < n_s - 1; ++k) {
      lx += x < cosines[k];
      ly += y < cosines[k];
      lz += z < cosines[k];
    }
    bin[c] = z == 0.0f ? n_s * n_s * n_s : (lx * n_s + ly) * n_s + lz;
  }
}

// Adds the x, y and z of a row's normals in bin `mode` into sums, normal c
// into lane c % kModeLanes of each coordinate's kModeLanes doubles: the
// compiler keeps one floating-point sum in order and scalar, lanes it
// vectorises.
constexpr int kModeLanes = 8;
RISAS_VECTOR_CLONES
void addModeRow(const float* __restrict xyz, const int* __restrict bin, int cols, int mode,
                double* __restrict sums) {
  const auto add = [&](int c, int lane) {
    // Weighed rather than selected: the compiler turns a selected value
    // into a masked load, which it does not vectorise.
    const double in = bin[c] == mode ? 1.0 : 0.0;
    for (int axis = 0; axis < 3; ++axis) sums[axis * kModeLanes + lane] += in * xyz[3 * c + axis];
  };
  int c = 0;
  for (; c + kModeLanes <= cols; c += kModeLanes) {
    for (int lane = 0; lane < kModeLanes; ++lane) add(c + lane, lane);
  }
  for (int lane = 0; c < cols; ++c, ++lane) add(c, lane);
}

}  // namespace

cv::Vec3i normalLabels(const cv::Vec3f& normal, int n_s) { return labelsOf(normal, SectorBoundaries(n_s)); }

namespace {

struct NormalBins {  // computeMainNormal
  std::vector<int> bin_of;
};
struct DotProductGridBuffers {  // dotProductGrid: P and its weight, and their smoothing
  cv::Mat p, weight;
  BlurredRows smoothed_p, smoothed_weight;
};
struct DotProductImageBuffers {  // dotProductImage: the grid, enlarged
  cv::Mat grid;
  EnlargedRows rows;
};

}  // namespace

cv::Vec3f computeMainNormal(const cv::Mat& normals, int n_s) {
  CV_Assert(normals.type() == CV_32FC3 && n_s >= 1);
  const int bins = n_s * n_s * n_s;  // bin `bins`: no normal
  const SectorBoundaries boundaries(n_s);
  // The bin of each normal.
  const int cols = normals.cols;
  std::vector<int>& bin_of = Workspace::ofThisThread().get<NormalBins>().bin_of;
  bin_of.resize(normals.total());
  for (int r = 0; r < normals.rows; ++r) {
    withDefault<DetectorParams::kDefaultN_s>(n_s, [&](auto fixed_n_s) {
      binRow(normals.ptr<float>(r), cols, boundaries.cosines.data(), fixed_n_s,
             bin_of.data() + static_cast<size_t>(r) * cols);
    });
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
  // The mean of the mode's normals, summed in double: the others masked
  // out, since branching on a normal's bin would mispredict.
  double sums[3 * kModeLanes] = {};
  for (int r = 0; r < normals.rows; ++r) {
    addModeRow(normals.ptr<float>(r), bin_of.data() + static_cast<size_t>(r) * cols, cols, mode, sums);
  }
  cv::Vec3d sum(0, 0, 0);
  for (int axis = 0; axis < 3; ++axis) {
    for (int lane = 0; lane < kModeLanes; ++lane) sum[axis] += sums[axis * kModeLanes + lane];
  }
  const cv::Vec3d mean = cv::normalize(sum);
  return cv::Vec3f(static_cast<float>(mean[0]), static_cast<float>(mean[1]), static_cast<float>(mean[2]));
}

void dotProductGrid(const FrameGeometry& geometry, const cv::Vec3f& n_main, double sigma, cv::Mat& grid) {
  const cv::Mat& normals = geometry.normals;
  CV_Assert(normals.type() == CV_32FC3);
  const int stride = geometry.normal_stride;
  DotProductGridBuffers& b = Workspace::ofThisThread().get<DotProductGridBuffers>();
  cv::Mat &p = b.p, &weight = b.weight;
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
  // Smoothed row by row (sigma 0: the kernel is [1]), each row divided as
  // soon as it is made. Far inside large holes the weight vanishes; those
  // pixels have no keypoints and no neighbour with one within the Harris
  // window, so 0 is as good as any value there.
  const std::vector<float> half = gaussianHalfKernel(sigma / stride);
  BlurredRows &smoothed_p = b.smoothed_p, &smoothed_weight = b.smoothed_weight;
  smoothed_p.reset(p, half, cv::BORDER_REPLICATE);
  smoothed_weight.reset(weight, half, cv::BORDER_REPLICATE);
  grid.create(p.size(), CV_32FC1);
  for (int r = 0; r < p.rows; ++r) {
    const float* pr = smoothed_p.row(r);
    const float* wr = smoothed_weight.row(r);
    float* out = grid.ptr<float>(r);
    for (int c = 0; c < p.cols; ++c) out[c] = wr[c] > 1e-3f ? pr[c] / wr[c] : 0.0f;
  }
}

void dotProductImage(const FrameGeometry& geometry, const cv::Vec3f& n_main, double sigma, cv::Mat& P) {
  DotProductImageBuffers& b = Workspace::ofThisThread().get<DotProductImageBuffers>();
  cv::Mat& grid = b.grid;
  EnlargedRows& rows = b.rows;
  dotProductGrid(geometry, n_main, sigma, grid);
  rows.reset(grid, geometry.normal_stride, geometry.size());
  P.create(geometry.size(), CV_32FC1);
  for (int y = 0; y < P.rows; ++y) std::copy_n(rows.row(y), P.cols, P.ptr<float>(y));
}

}  // namespace risas

// Paper III-B-3, readable: the disc sampled about the keypoint, each
// counted sample labelled (spatial sector, intensity rank group, shape rank
// group) and the labels counted into the histogram. encode runs the kernel
// (kernels/patch_encoding.cpp) unless cv::useOptimized() is false; tests
// hold the two equal.
#include "risas/encoding.hpp"

#include "risas/ranking.hpp"

#include "kernels/patch_encoding.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace risas {

void buildGreyPyramid(const cv::Mat& gray, int levels, GreyPyramid& pyramid) {
  CV_Assert(gray.type() == CV_8UC1 && levels >= 1);
  pyramid.level[0] = gray;
  pyramid.levels = 1;
  while (pyramid.levels < std::min(levels, GreyPyramid::kMaxLevels)) {
    const cv::Mat& finer = pyramid.level[pyramid.levels - 1];
    if (finer.cols < 4 || finer.rows < 4) break;  // the next would be under 2 x 2
    cv::pyrDown(finer, pyramid.level[pyramid.levels]);
    ++pyramid.levels;
  }
}

float blurLevel(double sigma_px, int levels) {
  const double lambda = 0.5 * std::log2(1.0 + 3.0 * sigma_px * sigma_px);
  return static_cast<float>(std::min<double>(lambda, levels - 1));
}

float sampleLevel(float radius_px, const DescriptorParams& params, int levels) {
  return blurLevel(params.sample_blur * radius_px / params.patch_radius, levels);
}

int pyramidLevelsNeeded(const DescriptorParams& params) {
  const double spacing = params.max_radius_px / params.patch_radius;  // the widest patch's
  const double blur = std::max(params.sample_blur, params.gradient_orientation ? kOrientationBlur : 0.0) * spacing;
  return static_cast<int>(std::ceil(blurLevel(blur, GreyPyramid::kMaxLevels))) + 1;
}

namespace {

// Bilinear on one level, at a point of that level clamped into it.
float bilinear(const cv::Mat& level, float x, float y) {
  const float xc = std::clamp(x, 0.0f, static_cast<float>(level.cols - 1));
  const float yc = std::clamp(y, 0.0f, static_cast<float>(level.rows - 1));
  const int u0 = std::min(static_cast<int>(xc), level.cols - 2), v0 = std::min(static_cast<int>(yc), level.rows - 2);
  const float a = xc - static_cast<float>(u0), b = yc - static_cast<float>(v0);
  const auto g = [&](int dv, int du) { return static_cast<float>(level.at<uchar>(v0 + dv, u0 + du)); };
  return (1.0f - b) * ((1.0f - a) * g(0, 0) + a * g(0, 1)) + b * ((1.0f - a) * g(1, 0) + a * g(1, 1));
}

}  // namespace

float greyAt(const GreyPyramid& pyramid, float lambda, float x, float y) {
  const int l = static_cast<int>(lambda);
  const float f = lambda - static_cast<float>(l);
  const float scale = std::ldexp(1.0f, -l);  // a power of two: exact
  const float finer = bilinear(pyramid.level[l], x * scale, y * scale);
  if (f == 0.0f) return finer;
  const float coarser = bilinear(pyramid.level[l + 1], x * scale * 0.5f, y * scale * 0.5f);
  return (1.0f - f) * finer + f * coarser;
}

PatchEncoder::PatchEncoder(const DescriptorParams& params) : params_(params) {
  params_.validate();
  const int r = params_.patch_radius;
  const double sector_angle = 2.0 * CV_PI / params_.n_pie;
  for (int j = -r; j <= r; ++j) {
    for (int i = -r; i <= r; ++i) {
      if (i * i + j * j > r * r) continue;
      double angle = std::atan2(static_cast<double>(j), static_cast<double>(i));
      if (angle < 0.0) angle += 2.0 * CV_PI;
      const int sector = std::min(params_.n_pie - 1, static_cast<int>(angle / sector_angle));
      // Equal-area rings: the share of the disc inside radius rho is rho^2.
      const int ring = std::min(params_.n_ring - 1, params_.n_ring * (i * i + j * j) / (r * r + 1));
      disc_i_.push_back(static_cast<float>(i) / r);
      disc_j_.push_back(static_cast<float>(j) / r);
      disc_sector_.push_back(static_cast<uint16_t>(ring * params_.n_pie + sector));
    }
  }
}

namespace {

// One counted sample's labels before ranking: its spatial label, its grey
// level (0..255) and its shape level (rho quantised, kFlat when rho >= rho-bar).
struct SampleLevels {
  int sector, grey, shape;
};
constexpr int kRhoLevels = 256, kFlat = kRhoLevels;

}  // namespace

bool PatchEncoder::encode(const GreyPyramid& grey, const FrameGeometry& geometry, const Neighbourhood& nb,
                          float radius_px, double theta, float* out) const {
  const float lambda = sampleLevel(radius_px, params_, grey.levels);
  if (cv::useOptimized()) {
    return encodePatchKernel(grey, lambda, geometry, nb, radius_px, theta, {disc_i_, disc_j_, disc_sector_}, params_,
                             out);
  }
  // The readable encoding, as the paper builds the histogram (III-B-3).
  const cv::Mat& gray = grey.level[0];
  const float cos_t = static_cast<float>(std::cos(theta)) * radius_px;
  const float sin_t = static_cast<float>(std::sin(theta)) * radius_px;
  const float t2 = static_cast<float>(params_.background_distance * params_.background_distance);
  const float rho_bar = static_cast<float>(params_.rho_threshold);
  const cv::Vec3f k(static_cast<float>(nb.point.x()), static_cast<float>(nb.point.y()),
                    static_cast<float>(nb.point.z()));
  const cv::Vec3f n_k(static_cast<float>(nb.normal.x()), static_cast<float>(nb.normal.y()),
                      static_cast<float>(nb.normal.z()));
  std::vector<SampleLevels> counted;
  for (size_t s = 0; s < disc_i_.size(); ++s) {
    // The sample's place in the image: the disc rotated by theta about the keypoint.
    const float x = nb.centre.x + cos_t * disc_i_[s] - sin_t * disc_j_[s];
    const float y = nb.centre.y + sin_t * disc_i_[s] + cos_t * disc_j_[s];
    if (!(x >= 0.0f && y >= 0.0f && x <= gray.cols - 1 && y <= gray.rows - 1)) continue;
    // It counts when its nearest pixel has a normal and is foreground (eq. 5).
    const int u = static_cast<int>(std::nearbyint(x)), v = static_cast<int>(std::nearbyint(y));
    if (!geometry.hasNormal(v, u)) continue;
    const cv::Vec3f p = geometry.point(v, u) - k;
    if (!(p.dot(p) < t2)) continue;
    // Grey level: read at the patch's pyramid level, rounded.
    const float intensity = greyAt(grey, lambda, x, y);
    // Shape: rho = |n_k . n_i| (eq. 8); the flat majority at or above rho-bar
    // is one level, the rest are ranked on rho / rho-bar.
    const float rho = std::abs(n_k.dot(geometry.normal(v, u)));
    const int shape = rho >= rho_bar ? kFlat : std::min(static_cast<int>(rho / rho_bar * kRhoLevels), kRhoLevels - 1);
    counted.push_back({disc_sector_[s], static_cast<int>(intensity + 0.5f), shape});
  }
  const int n = static_cast<int>(disc_i_.size());
  if (counted.size() < params_.min_valid_fraction * n || counted.size() < 3) return false;

  // Intensity label: the grey level's rank group among the counted samples;
  // shape label: the shape level's rank group among the non-flat ones, the
  // flat ones n_vec; with n_vec 0 no shape labels, every sample label 0.
  std::vector<uint16_t> greys, shapes;
  for (const SampleLevels& c : counted) {
    greys.push_back(static_cast<uint16_t>(c.grey));
    if (c.shape != kFlat) shapes.push_back(static_cast<uint16_t>(c.shape));
  }
  std::vector<uint8_t> intensity_label, shape_rank(shapes.size(), 0);
  rankGroups(greys, 256, params_.n_bin, intensity_label);
  if (params_.n_vec > 0) rankGroups(shapes, kRhoLevels, params_.n_vec, shape_rank);

  // Soft binning's rank groups: each grey level's two nearest groups by its
  // mid-rank under the grey image's noise, and the upper one's weight.
  uint8_t lower_group[256] = {};
  float upper_group_weight[256] = {};
  if (params_.soft_binning) {
    std::vector<int> grey_count(256, 0);
    for (const SampleLevels& c : counted) ++grey_count[static_cast<size_t>(c.grey)];
    rankPositionTable(grey_count.data(), 256, params_.n_bin, grey.noise, lower_group, upper_group_weight);
  }

  // The joint histogram (eq. 8): bins (sector, intensity group, shape
  // label). With a shape histogram of its own (shape_weight), the intensity
  // bins take no shape label, and the shape histogram's bins (sector, shape
  // label) follow them.
  const bool own_shape = params_.ownShapeHistogram();
  const int n_shape = params_.n_vec + 1, joint_shapes = own_shape ? 1 : n_shape;
  const int intensity_bins = params_.n_ring * params_.n_pie * params_.n_bin * joint_shapes;
  std::vector<float> histogram(static_cast<size_t>(dimension()), 0.0f);
  const auto vote = [&](int sector, int group, int shape_label, float weight) {
    const int joint_label = own_shape ? 0 : shape_label;
    histogram[static_cast<size_t>((sector * params_.n_bin + group) * joint_shapes + joint_label)] += weight;
  };
  size_t ranked = 0;
  for (size_t c = 0; c < counted.size(); ++c) {
    const int shape_label = counted[c].shape == kFlat ? params_.n_vec : shape_rank[ranked++];
    if (own_shape) histogram[static_cast<size_t>(intensity_bins + counted[c].sector * n_shape + shape_label)] += 1.0f;
    if (!params_.soft_binning) {
      vote(counted[c].sector, intensity_label[c], shape_label, 1.0f);
      continue;
    }
    const int g = counted[c].grey, lower = lower_group[g], upper = std::min(lower + 1, params_.n_bin - 1);
    vote(counted[c].sector, lower, shape_label, 1.0f - upper_group_weight[g]);
    vote(counted[c].sector, upper, shape_label, upper_group_weight[g]);
  }
  if (own_shape) {  // each part to unit length, the shape part then to shape_weight
    const auto scale_to = [&](int begin, int end, double length) {
      cv::Mat part(1, end - begin, CV_32F, histogram.data() + begin);  // a header on the histogram's bins
      part *= length / cv::norm(part);
    };
    scale_to(0, intensity_bins, 1.0);
    scale_to(intensity_bins, dimension(), params_.shape_weight);
  }
  const double norm = cv::norm(histogram);
  for (int i = 0; i < dimension(); ++i) out[i] = static_cast<float>(histogram[static_cast<size_t>(i)] / norm);
  return true;
}

}  // namespace risas

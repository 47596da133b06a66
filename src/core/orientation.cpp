#include "risas/orientation.hpp"

#include "risas/orientation_histogram.hpp"

#include "kernels/gradient_orientation.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>

#include <cmath>
#include <vector>

namespace risas {
namespace {

// Image direction of a 3D direction d at point p: the Jacobian of the
// pinhole projection applied to d.
Eigen::Vector2d projectDirection(const Eigen::Vector3d& d, const Eigen::Vector3d& p, const Intrinsics& K) {
  const double z = p.z();
  return {K.fx * (d.x() * z - p.x() * d.z()) / (z * z), K.fy * (d.y() * z - p.y() * d.z()) / (z * z)};
}

double angleOf(const Eigen::Vector2d& d) { return std::atan2(d.y(), d.x()); }

// The disc's unrotated sample grid (patch_radius samples per radius), out
// to one sample around the disc and kBlurReach beyond, row by row.
struct OrientationGrid {
  int half = 0, side = 0;        // samples from the centre to the edge; 2 half + 1
  std::vector<SampleKind> kind;
  std::vector<float> grey;       // read for Counted samples within the disc and one sample around it
  size_t at(int i, int j) const { return static_cast<size_t>((j + half) * side + (i + half)); }
};

// The grid about the keypoint, `spacing` pixels a sample, into g; the grey
// read at fractional level lambda.
void fillOrientationGrid(const GreyPyramid& grey, float lambda, const FrameGeometry& geometry, const Neighbourhood& nb,
                         float spacing, int radius, double background_distance, OrientationGrid& g) {
  g.half = radius + 1 + kBlurReach, g.side = 2 * g.half + 1;
  g.kind.assign(static_cast<size_t>(g.side * g.side), SampleKind::Background);
  g.grey.assign(g.kind.size(), 0.0f);
  const cv::Size size = geometry.depth.size();
  const cv::Vec3f k(static_cast<float>(nb.point.x()), static_cast<float>(nb.point.y()), static_cast<float>(nb.point.z()));
  const float t2 = static_cast<float>(background_distance * background_distance);
  for (int j = -g.half; j <= g.half; ++j) {
    for (int i = -g.half; i <= g.half; ++i) {
      const float x = nb.centre.x + spacing * static_cast<float>(i), y = nb.centre.y + spacing * static_cast<float>(j);
      if (!(x >= 0.0f && y >= 0.0f && x <= size.width - 1 && y <= size.height - 1)) continue;
      const int u = static_cast<int>(std::nearbyint(x)), v = static_cast<int>(std::nearbyint(y));
      SampleKind& kind = g.kind[g.at(i, j)];
      if (!geometry.hasPoint(v, u)) {
        kind = SampleKind::Uncounted;
        continue;
      }
      const cv::Vec3f p = geometry.point(v, u) - k;
      if (!(p.dot(p) < t2)) continue;  // Background
      if (!geometry.hasNormal(v, u)) {
        kind = SampleKind::Uncounted;
        continue;
      }
      kind = SampleKind::Counted;
      if (std::abs(i) <= radius + 1 && std::abs(j) <= radius + 1) g.grey[g.at(i, j)] = greyAt(grey, lambda, x, y);
    }
  }
}

// Which grid samples have no Background sample within kBlurReach in rows
// and columns (a separable erosion; past the grid's edge counts as
// Background).
std::vector<char> clearOfTheBackground(const OrientationGrid& g) {
  std::vector<char> row_clear(g.kind.size(), 0), clear(g.kind.size(), 0);
  for (int j = -g.half; j <= g.half; ++j) {
    for (int i = -g.half + kBlurReach; i <= g.half - kBlurReach; ++i) {
      bool ok = true;
      for (int d = -kBlurReach; d <= kBlurReach && ok; ++d) ok = g.kind[g.at(i + d, j)] != SampleKind::Background;
      row_clear[g.at(i, j)] = ok;
    }
  }
  for (int j = -g.half + kBlurReach; j <= g.half - kBlurReach; ++j) {
    for (int i = -g.half; i <= g.half; ++i) {
      bool ok = true;
      for (int d = -kBlurReach; d <= kBlurReach && ok; ++d) ok = row_clear[g.at(i, j + d)];
      clear[g.at(i, j)] = ok;
    }
  }
  return clear;
}

}  // namespace

Orientation dominantOrientation(const Neighbourhood& nb, const Intrinsics& intrinsics, const DescriptorParams& params) {
  const double gamma = params.gamma;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(nb.covariance);  // ascending
  const Eigen::Vector3d e = solver.eigenvalues();
  const double e1 = e(2), e2 = e(1), e3 = e(0);
  const Eigen::Vector3d v1 = solver.eigenvectors().col(2);
  const Eigen::Vector3d v2 = solver.eigenvectors().col(1);

  Orientation result;
  Eigen::Vector3d d3d;
  if (e2 > gamma * e1 && e3 > gamma * e1) {
    return result;  // rejected
  } else if (e2 > gamma * e1) {
    result.source = OrientationSource::PatchNormal;
    d3d = v1.cross(v2).normalized();
    if (d3d.dot(nb.point) > 0.0) d3d = -d3d;  // face the camera
  } else {
    result.source = OrientationSource::MajorAxis;
    d3d = v1;
  }

  const Eigen::Vector2d& centroid = nb.intensity_centroid;
  const double sin_to_ray = d3d.cross(nb.point.normalized()).norm();
  if (!params.shape_orientation || sin_to_ray < std::sin(params.min_projection_angle_deg * CV_PI / 180.0)) {
    result.source = OrientationSource::IntensityCentroid;
    result.theta = angleOf(centroid);  // atan2(0, 0) = 0 for a flat patch
    return result;
  }
  Eigen::Vector2d d2d = projectDirection(d3d, nb.point, intrinsics);
  if (result.source == OrientationSource::MajorAxis && d2d.dot(centroid) < 0.0) d2d = -d2d;
  result.theta = angleOf(d2d);
  return result;
}

bool intensityCentroidNeeded(const DescriptorParams& params) {
  return params.shape_orientation || !params.gradient_orientation;
}

double gradientOrientation(const GreyPyramid& grey, const FrameGeometry& geometry, const Neighbourhood& nb,
                           float radius_px, const DescriptorParams& params) {
  if (cv::useOptimized() && gradientOrientationKernelFits(params)) {
    return gradientOrientationKernel(grey, geometry, nb, radius_px, params);
  }
  // The readable rule, sample by sample.
  const int steps = params.patch_radius;
  const float spacing = radius_px / static_cast<float>(steps);
  OrientationGrid g;
  fillOrientationGrid(grey, blurLevel(kOrientationBlur * spacing, grey.levels), geometry, nb, spacing, steps,
                      params.background_distance, g);
  const std::vector<char> clear = clearOfTheBackground(g);
  const auto counted = [&](int i, int j) { return g.kind[g.at(i, j)] == SampleKind::Counted; };
  // A Gaussian as wide as the disc, separable: its factor per row or column.
  std::vector<double> gaussian(static_cast<size_t>(2 * steps + 1));
  for (int i = -steps; i <= steps; ++i) gaussian[static_cast<size_t>(i + steps)] = std::exp(-0.5 * i * i / (steps * steps));
  // Each counted sample of the disc, clear of the background, whose four
  // neighbours are counted too votes its gradient (central differences):
  // its magnitude times the Gaussian, into the two bins nearest its
  // direction.
  OrientationHistogram histogram{};
  for (int j = -steps; j <= steps; ++j) {
    for (int i = -steps; i <= steps; ++i) {
      if (i * i + j * j > steps * steps || !clear[g.at(i, j)] || !counted(i, j) || !counted(i - 1, j) ||
          !counted(i + 1, j) || !counted(i, j - 1) || !counted(i, j + 1)) {
        continue;
      }
      const float gx = g.grey[g.at(i + 1, j)] - g.grey[g.at(i - 1, j)];
      const float gy = g.grey[g.at(i, j + 1)] - g.grey[g.at(i, j - 1)];
      if (gx == 0.0f && gy == 0.0f) continue;
      const double weight = std::sqrt(gx * gx + gy * gy) * gaussian[static_cast<size_t>(i + steps)] *
                            gaussian[static_cast<size_t>(j + steps)];
      voteDirection(histogram, cv::fastAtan2(gy, gx), weight);
    }
  }
  return histogramPeak(histogram);
}

}  // namespace risas

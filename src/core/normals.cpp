// Paper III-A step 1, readable: depth -> organised points -> a normal per
// block of normal_stride x normal_stride pixels, the direction of least
// variance (PCA) of the points in a square window on the block's own
// surface. estimateNormals runs the kernel (kernels/normal_fit.cpp) unless
// cv::useOptimized() is false; tests hold the two equal.
#include "risas/geometry.hpp"

#include "kernels/normal_fit.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace risas {
namespace {

bool sameSurface(float z, float neighbour, float depth_change_factor) {
  return std::abs(neighbour - z) <= depth_change_factor * z;  // false when either is NaN
}

// The block means: per block, the mean of its points on the same surface as
// its first valid point (row-major), and on_block_surface marking those
// pixels. CV_32FC3, NaN where a block has no point.
cv::Mat blockMeans(const cv::Mat& depth, const std::vector<float>& x_factor, const std::vector<float>& y_factor,
                   int stride, float depth_change_factor, cv::Mat& on_block_surface) {
  const int rows = depth.rows, cols = depth.cols;
  cv::Mat means((rows + stride - 1) / stride, (cols + stride - 1) / stride, CV_32FC3);
  on_block_surface.create(depth.size(), CV_8UC1);
  for (int i = 0; i < means.rows; ++i) {
    for (int j = 0; j < means.cols; ++j) {
      const cv::Rect block = cv::Rect(j * stride, i * stride, stride, stride) & cv::Rect(0, 0, cols, rows);
      float first = NAN;
      for (int r = block.y; r < block.br().y && std::isnan(first); ++r) {
        for (int c = block.x; c < block.br().x && std::isnan(first); ++c) first = depth.at<float>(r, c);
      }
      cv::Vec3d sum(0, 0, 0);
      int n = 0;
      for (int r = block.y; r < block.br().y; ++r) {
        for (int c = block.x; c < block.br().x; ++c) {
          const float z = depth.at<float>(r, c);
          const bool on = sameSurface(first, z, depth_change_factor);
          on_block_surface.at<uchar>(r, c) = on ? 255 : 0;
          if (on) sum += cv::Vec3d(x_factor[size_t(c)] * z, y_factor[size_t(r)] * z, z), ++n;
        }
      }
      means.at<cv::Vec3f>(i, j) = n ? cv::Vec3f(sum / n) : cv::Vec3f(NAN, NAN, NAN);
    }
  }
  return means;
}

// The surfaces of the grid: connected parts (4-neighbours) of its interior,
// the points with a point and no depth jump to any 4-neighbour (outside the
// grid counts as the point itself). Label 0: a border point, on no surface.
cv::Mat surfaceLabels(const cv::Mat& points, float depth_change_factor) {
  cv::Mat interior(points.size(), CV_8UC1);
  for (int v = 0; v < points.rows; ++v) {
    for (int u = 0; u < points.cols; ++u) {
      const float z = points.at<cv::Vec3f>(v, u)[2];
      const auto zAt = [&](int r, int c) {
        return points.at<cv::Vec3f>(std::clamp(r, 0, points.rows - 1), std::clamp(c, 0, points.cols - 1))[2];
      };
      const bool inside = sameSurface(z, zAt(v - 1, u), depth_change_factor) &&
                          sameSurface(z, zAt(v + 1, u), depth_change_factor) &&
                          sameSurface(z, zAt(v, u - 1), depth_change_factor) &&
                          sameSurface(z, zAt(v, u + 1), depth_change_factor);
      interior.at<uchar>(v, u) = inside ? 255 : 0;
    }
  }
  cv::Mat labels;
  cv::connectedComponents(interior, labels, 4, CV_32S);
  return labels;
}

}  // namespace

cv::Mat pcaNormals(const cv::Mat& points, const cv::Mat& labels, int radius, int min_points) {
  // A covariance whose two largest eigenvalues' product is below this share
  // of its squared trace is a line, not a plane: no normal.
  constexpr double kMinPlaneness = 1e-6;
  cv::Mat normals(points.size(), CV_32FC3, cv::Scalar::all(0));
  for (int v = 0; v < points.rows; ++v) {
    for (int u = 0; u < points.cols; ++u) {
      const int label = labels.at<int>(v, u);
      if (label == 0) continue;
      // The window's points on the centre's surface, about the centre.
      const cv::Vec3d centre = points.at<cv::Vec3f>(v, u);
      cv::Matx33d scatter = cv::Matx33d::zeros();
      cv::Vec3d sum(0, 0, 0);
      int n = 0;
      for (int r = std::max(v - radius, 0); r <= std::min(v + radius, points.rows - 1); ++r) {
        for (int c = std::max(u - radius, 0); c <= std::min(u + radius, points.cols - 1); ++c) {
          if (labels.at<int>(r, c) != label) continue;
          const cv::Vec3d p = cv::Vec3d(points.at<cv::Vec3f>(r, c)) - centre;
          scatter += p * p.t();
          sum += p;
          ++n;
        }
      }
      if (n < min_points) continue;
      const cv::Vec3d mean = sum / n;
      const cv::Matx33d covariance = scatter * (1.0 / n) - mean * mean.t();
      cv::Vec3d eigenvalues;  // descending
      cv::Matx33d eigenvectors;
      cv::eigen(covariance, eigenvalues, eigenvectors);
      const double trace = eigenvalues[0] + eigenvalues[1] + eigenvalues[2];
      if (!(trace > 0.0) || eigenvalues[0] * eigenvalues[1] < kMinPlaneness * trace * trace) continue;
      cv::Vec3d normal(eigenvectors(2, 0), eigenvectors(2, 1), eigenvectors(2, 2));  // the smallest's
      if (normal.dot(centre) > 0.0) normal = -normal;  // facing the camera
      normals.at<cv::Vec3f>(v, u) = cv::Vec3f(cv::normalize(normal));
    }
  }
  return normals;
}

void estimateNormals(const cv::Mat& depth_metres, const Intrinsics& intrinsics, const GeometryParams& params,
                     cv::Mat& normals, cv::Mat& on_block_surface) {
  estimateNormals(depth_metres, rayFactors(depth_metres.cols, intrinsics.cx, intrinsics.fx),
                  rayFactors(depth_metres.rows, intrinsics.cy, intrinsics.fy), params, normals, on_block_surface);
}

void estimateNormals(const cv::Mat& depth_metres, const std::vector<float>& x_factor,
                     const std::vector<float>& y_factor, const GeometryParams& params, cv::Mat& normals,
                     cv::Mat& on_block_surface) {
  CV_Assert(depth_metres.type() == CV_32FC1);
  CV_Assert(x_factor.size() == static_cast<size_t>(depth_metres.cols) &&
            y_factor.size() == static_cast<size_t>(depth_metres.rows));
  if (cv::useOptimized()) {
    normalFitKernel(depth_metres, x_factor, y_factor, params, normals, on_block_surface);
    return;
  }
  // On the grid, a jump is measured over stride pixels and the window holds
  // the grid points within normal_radius pixels of the centre.
  const int stride = params.normal_stride;
  const float factor = static_cast<float>(params.depth_change_factor);
  const int grid_radius = std::max(1, (params.normal_radius + stride - 1) / stride);
  const cv::Mat means = blockMeans(depth_metres, x_factor, y_factor, stride, factor, on_block_surface);
  normals = pcaNormals(means, surfaceLabels(means, factor * stride), grid_radius, params.min_normal_points);
}

}  // namespace risas

#include "risas/neighbourhood.hpp"

#include "risas/ranking.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <vector>

namespace risas {

float depthScale(float depth) { return std::max(0.2f, (3.8f - 0.4f * std::max(2.0f, depth)) / 3.0f); }

float initialRadius(float s, float s_min, float s_max) {
  const float ratio = std::max(0.2f, s_max) / std::max(0.2f, s_min);
  return (-5.0f + 25.0f * std::min(3.0f, ratio)) * s;
}

float patchRadius(float depth, const ScaleRange& scales, double support_radius, const Intrinsics& intrinsics) {
  if (support_radius > 0.0) return static_cast<float>(0.5 * (intrinsics.fx + intrinsics.fy) * support_radius / depth);
  return initialRadius(depthScale(depth), scales.s_min, scales.s_max);
}

ScaleRange frameScaleRange(const cv::Mat& depth_metres) {
  CV_Assert(depth_metres.type() == CV_32FC1);
  // Depth histogram in centimetres up to 20 m: percentiles without a sort.
  constexpr int kBins = 2001;
  std::vector<int> histogram(kBins, 0);
  int total = 0;
  for (int r = 0; r < depth_metres.rows; ++r) {
    const float* d = depth_metres.ptr<float>(r);
    for (int c = 0; c < depth_metres.cols; ++c) {
      if (std::isnan(d[c])) continue;
      ++histogram[std::min(kBins - 1, static_cast<int>(d[c] * 100.0f))];
      ++total;
    }
  }
  if (total == 0) return {};
  const auto percentile = [&](double q) {
    const int target = static_cast<int>(q * (total - 1));
    int seen = 0;
    for (int b = 0; b < kBins; ++b) {
      seen += histogram[b];
      if (seen > target) return (b + 0.5f) / 100.0f;
    }
    return (kBins - 0.5f) / 100.0f;
  };
  return {depthScale(percentile(0.99)), depthScale(percentile(0.01))};
}

std::optional<Neighbourhood> selectNeighbourhood(const RgbdFrame& frame, const FrameGeometry& geometry,
                                                 const cv::Point2f& keypoint, float initial_radius_px,
                                                 double background_distance) {
  const int u0 = cvRound(keypoint.x), v0 = cvRound(keypoint.y);
  const cv::Size size = frame.size();
  if (u0 < 0 || v0 < 0 || u0 >= size.width || v0 >= size.height) return std::nullopt;
  if (!geometry.hasPoint(v0, u0) || !geometry.hasNormal(v0, u0)) return std::nullopt;

  Neighbourhood nb;
  nb.centre = keypoint;
  const cv::Vec3f k = geometry.points.at<cv::Vec3f>(v0, u0);
  const cv::Vec3f n = geometry.normals.at<cv::Vec3f>(v0, u0);
  nb.point = Eigen::Vector3d(k[0], k[1], k[2]);
  nb.normal = Eigen::Vector3d(n[0], n[1], n[2]);
  nb.initial_radius_px = initial_radius_px;

  const int radius = static_cast<int>(std::ceil(initial_radius_px));
  const double t2 = background_distance * background_distance;
  const float r2 = initial_radius_px * initial_radius_px;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_outer = Eigen::Matrix3d::Zero();
  std::vector<uint16_t> intensities;
  std::vector<cv::Point> offsets;
  for (int dv = -radius; dv <= radius; ++dv) {
    const int v = v0 + dv;
    if (v < 0 || v >= size.height) continue;
    const cv::Vec3f* p = geometry.points.ptr<cv::Vec3f>(v);
    const uchar* gray = frame.gray().ptr<uchar>(v);
    for (int du = -radius; du <= radius; ++du) {
      const int u = u0 + du;
      if (u < 0 || u >= size.width || static_cast<float>(du * du + dv * dv) > r2) continue;
      if (std::isnan(p[u][2])) continue;
      const Eigen::Vector3d q(p[u][0], p[u][1], p[u][2]);
      const Eigen::Vector3d d = q - nb.point;
      if (d.squaredNorm() >= t2) continue;  // eq. 5: background
      ++nb.kept;
      sum += d;
      sum_outer += d * d.transpose();
      intensities.push_back(gray[u]);
      offsets.emplace_back(du, dv);
    }
  }
  if (nb.kept < 3) return std::nullopt;
  const double inv = 1.0 / nb.kept;
  const Eigen::Vector3d mean_offset = sum * inv;
  nb.centroid = nb.point + mean_offset;
  nb.spread = sum_outer * inv;
  nb.covariance = nb.spread - mean_offset * mean_offset.transpose();
  // The intensity centroid from ranks, not intensities, so that a monotonic
  // illumination change cannot turn it: sum (rank - mean rank)(q - k).
  // Tied pixels take the middle rank of their run: a run of equal values
  // (a dark area that a cube transform flattened) then weighs as it would had
  // its pixels differed, which keeps the centroid's direction. The mean
  // middle rank is (n - 1) / 2.
  std::vector<int> rank;
  ranks(intensities, 256, rank);
  std::vector<int> run(256, 0);
  for (uint16_t v : intensities) ++run[v];
  const double mean_rank = 0.5 * (nb.kept - 1);
  nb.intensity_centroid.setZero();
  for (size_t i = 0; i < rank.size(); ++i) {
    const double mid_rank = rank[i] + 0.5 * (run[intensities[i]] - 1);
    nb.intensity_centroid += (mid_rank - mean_rank) * Eigen::Vector2d(offsets[i].x, offsets[i].y);
  }
  return nb;
}

float ellipseRadius(const Neighbourhood& nb, const Intrinsics& intrinsics, double min_px, double max_px) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(nb.spread, Eigen::EigenvaluesOnly);
  const double major_semi_axis = 2.0 * std::sqrt(std::max(0.0, solver.eigenvalues()(2)));
  const double focal = 0.5 * (intrinsics.fx + intrinsics.fy);
  const double projected = major_semi_axis * focal / nb.point.z();
  const double upper = std::min<double>(nb.initial_radius_px, max_px);
  return static_cast<float>(std::clamp(projected, std::min(min_px, upper), upper));
}

}  // namespace risas

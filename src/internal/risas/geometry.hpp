// Paper III-A step 1: depth -> organised point cloud -> surface normals.
// Computed once per frame and shared by the detector and the descriptor.
#pragma once

#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <opencv2/core.hpp>

#include <cmath>
#include <vector>

namespace risas {

struct FrameGeometry {
  // The organised point cloud, kept as the frame's depth (CV_32FC1, metres,
  // NaN where missing; it shares the frame's data) and the back-projection
  // factors of its intrinsics (rayFactors): point(row, col) is
  // (x_factor[col] z, y_factor[row] z, z), camera optical frame; no point
  // image is formed (docs/performance.md says why). backProject gives the
  // same points as an image.
  cv::Mat depth;
  std::vector<float> x_factor, y_factor;

  // The normals are fitted once per block of normal_stride x normal_stride
  // pixels (GeometryParams::normal_stride), at the mean of the block's points
  // on one surface: neighbouring pixels share almost all of their window, so
  // a fit per pixel would repeat the same normal. A pixel's normal is its
  // block's, if the pixel lies on the surface the block's fit belongs to.
  int normal_stride = 1;
  cv::Mat normals;           // CV_32FC3 per block, unit, facing the camera (n . p < 0); (0,0,0) where none
  cv::Mat on_block_surface;  // CV_8UC1 per pixel: 255 where the pixel lies on its block's surface

  cv::Size size() const { return depth.size(); }
  // Whether this is the geometry of a frame of `frame_size`, complete.
  bool fits(cv::Size frame_size) const {
    return size() == frame_size && depth.type() == CV_32FC1 &&
           x_factor.size() == static_cast<size_t>(frame_size.width) &&
           y_factor.size() == static_cast<size_t>(frame_size.height) && !normals.empty() &&
           on_block_surface.size() == frame_size;
  }
  bool hasPoint(int row, int col) const { return !std::isnan(depth.at<float>(row, col)); }
  // NaN where there is no point.
  cv::Vec3f point(int row, int col) const {
    const float z = depth.at<float>(row, col);
    return {x_factor[static_cast<size_t>(col)] * z, y_factor[static_cast<size_t>(row)] * z, z};
  }
  // The normal of pixel (row, col): (0, 0, 0) unless hasNormal.
  const cv::Vec3f& normal(int row, int col) const {
    return normals.at<cv::Vec3f>(row / normal_stride, col / normal_stride);
  }
  bool hasNormal(int row, int col) const {
    return on_block_surface.at<uchar>(row, col) != 0 && normal(row, col)[2] != 0.0f;
  }
};

// The functions with an output argument reuse its buffers when they already
// have the size and type (cv::Mat::create), so a caller processing a stream
// may keep one FrameGeometry. The output must not share data with anything
// still in use.

// Back-projects every pixel with fx and fy (the reference used fx for both).
// x = (u - cx) z / fx, so the factor of z is one per column (and per row for
// y): rayFactors(cols, cx, fx) tabulates them, and backProject and the
// normals' grid share it, so they give the very same points.
std::vector<float> rayFactors(int count, double centre, double focal);
void backProject(const cv::Mat& depth_metres, const Intrinsics& intrinsics, cv::Mat& points);
cv::Mat backProject(const cv::Mat& depth_metres, const Intrinsics& intrinsics);

// Normals as PCL's IntegralImageNormalEstimation (COVARIANCE_MATRIX) does
// them: the covariance of the points in a square window comes from box sums
// of the point moments in O(1) per pixel (sliding sums, where PCL uses
// integral images), and its smallest eigenvector
// (power iteration on its adjugate, no trigonometry) is the normal. A window
// never mixes two surfaces: near a depth jump it takes only the points of the
// centre's own surface (PCL uses a depth-change map for the same purpose).
// The fits run on a grid of normal_stride x normal_stride block means (the
// window holds the grid points within normal_radius pixels): normals has one
// per block, on_block_surface marks the pixels each belongs to (see
// FrameGeometry). The block means come straight from the depth (CV_32FC1,
// metres, NaN where missing), back-projected as backProject does it.
void estimateNormals(const cv::Mat& depth_metres, const Intrinsics& intrinsics, const GeometryParams& params,
                     cv::Mat& normals, cv::Mat& on_block_surface);
// The same with the back-projection factors already tabulated (rayFactors),
// as computeGeometry has them for FrameGeometry.
void estimateNormals(const cv::Mat& depth_metres, const std::vector<float>& x_factor,
                     const std::vector<float>& y_factor, const GeometryParams& params, cv::Mat& normals,
                     cv::Mat& on_block_surface);

// The fit itself, readable (normals.cpp): at every point of `points`
// (CV_32FC3, NaN where none) with a surface label (CV_32S, 0: none), the
// unit eigenvector of the smallest eigenvalue of the covariance of the
// points within `radius` that carry the same label, facing the camera;
// (0, 0, 0) where fewer than min_points, or where they lie on a line.
cv::Mat pcaNormals(const cv::Mat& points, const cv::Mat& labels, int radius, int min_points);

void computeGeometry(const RgbdFrame& frame, const GeometryParams& params, FrameGeometry& geometry);
FrameGeometry computeGeometry(const RgbdFrame& frame, const GeometryParams& params);

}  // namespace risas

// Paper III-B-1: scale estimation and neighbourhood selection.
#pragma once

#include "risas/geometry.hpp"
#include "risas/rgbd_frame.hpp"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <optional>

namespace risas {

// Eq. 3 (from BRAND/LOIND): s = max(0.2, (3.8 - 0.4 max(2, d)) / 3), d in metres.
float depthScale(float depth);

// Eq. 4: R = (-5 + 25 min(3, max(0.2, s_max) / max(0.2, s_min))) s, pixels.
// (The paper's "max(0.2.s_max)" is a typo for max(0.2, s_max).)
float initialRadius(float s, float s_min, float s_max);

// s_min and s_max of eq. 4: the scales of the frame's farthest and nearest
// depths. The 1st and 99th depth percentiles stand for them, so that one stray
// pixel does not change every patch of the frame.
struct ScaleRange {
  float s_min = 1.0f;
  float s_max = 1.0f;
};
ScaleRange frameScaleRange(const cv::Mat& depth_metres);

// The initial patch radius R in pixels of a keypoint at `depth`: eq. 3 and 4
// with support_radius = 0, else the projection of a disc of support_radius
// metres (see DescriptorParams::support_radius).
float patchRadius(float depth, const ScaleRange& scales, double support_radius, const Intrinsics& intrinsics);

// The foreground around a keypoint: the points of the disc of radius R around
// it that lie within t of its 3D point (eq. 5), summarised by the moments the
// later steps need.
struct Neighbourhood {
  cv::Point2f centre;              // keypoint pixel
  Eigen::Vector3d point;           // k_i, metres
  Eigen::Vector3d normal;          // n_{p_k}, unit, facing the camera
  float initial_radius_px = 0.0f;  // R of eq. 4
  int kept = 0;                    // |P-bar^xyz(k_i)|
  Eigen::Vector3d centroid;        // of the kept points
  Eigen::Matrix3d covariance;      // of the kept points about their centroid (PCA, III-B-2)
  Eigen::Matrix3d spread;          // mean (p - k_i)(p - k_i)^T: the ellipse about k_i
  // sum (rank(I) - mean rank)(q - k) over the kept pixels q: where the
  // patch is brighter, in pixels, unchanged by monotonic intensity changes.
  Eigen::Vector2d intensity_centroid = Eigen::Vector2d::Zero();
};

// None when the keypoint has no 3D point or normal or too few foreground
// neighbours to describe. Without `with_intensity_centroid` the
// intensity_centroid stays zero and every other field is the same: it is
// the grey levels' share of the work, and theta from the patch's gradients
// does not read it (intensityCentroidNeeded).
std::optional<Neighbourhood> selectNeighbourhood(const RgbdFrame& frame, const FrameGeometry& geometry,
                                                 const cv::Point2f& keypoint, float initial_radius_px,
                                                 double background_distance, bool with_intensity_centroid = true);

// Eq. 6 and what follows it: the ellipse centred at k_i with the second
// moments of the kept points, projected into the image, gives the patch
// radius R-bar. For a full disc of radius R on a plane facing the camera the
// major semi-axis 2 sqrt(e1) is exactly R; background elimination shrinks it.
// Clamped to [min_px, min(R, max_px)].
float ellipseRadius(const Neighbourhood& neighbourhood, const Intrinsics& intrinsics, double min_px,
                    double max_px);

}  // namespace risas

// The one list of every parameter's name and valid range. cv::FileStorage
// read/write, validation and the ROS parameter server all visit this list, so
// they can never disagree about a name or a range.
//
// A visitor is called as v(name, value&, lo, hi) for numbers and
// v(name, bool&) for flags.
#pragma once

#include "risas/params.hpp"

namespace risas {

template <class V>
void visitFields(GeometryParams& p, V&& v) {
  v("normal_radius", p.normal_radius, 1, 50);
  v("depth_change_factor", p.depth_change_factor, 1e-4, 1.0);
  v("min_normal_points", p.min_normal_points, 3, 10000);
  v("normal_stride", p.normal_stride, 1, 8);
}

template <class V>
void visitFields(DetectorParams& p, V&& v) {
  v("tau", p.tau, 0.0, 1.0);
  v("n_s", p.n_s, 2, 64);
  v("harris_k", p.harris_k, 0.0, 0.25);
  v("gray_sigma", p.gray_sigma, 0.0, 20.0);
  v("dp_sigma", p.dp_sigma, 0.0, 20.0);
  v("window_sigma", p.window_sigma, 0.3, 20.0);
  v("response_threshold", p.response_threshold, 0.0, 1.0);
  v("nms_radius", p.nms_radius, 1, 50);
  v("max_keypoints", p.max_keypoints, 1, 20000);
  v("min_keypoints", p.min_keypoints, 0, 20000);
  v("grid_cols", p.grid_cols, 1, 256);
  v("grid_rows", p.grid_rows, 1, 256);
  v("border", p.border, 0, 1000);
}

template <class V>
void visitFields(DescriptorParams& p, V&& v) {
  v("gamma", p.gamma, 0.0, 1.0);
  v("n_pie", p.n_pie, 1, 64);
  v("n_bin", p.n_bin, 1, 256);
  v("n_vec", p.n_vec, 0, 64);
  v("n_ring", p.n_ring, 1, 8);
  v("shape_weight", p.shape_weight, 0.0, 100.0);
  v("soft_binning", p.soft_binning);
  v("sample_blur", p.sample_blur, 0.0, 4.0);
  v("grey_noise", p.grey_noise, -1.0, 64.0);
  v("rho_threshold", p.rho_threshold, 0.0, 1.0);
  v("support_radius", p.support_radius, 0.0, 1.0);
  v("background_distance", p.background_distance, 1e-3, 10.0);
  v("patch_radius", p.patch_radius, 4, 100);
  v("min_radius_px", p.min_radius_px, 1.0, 1000.0);
  v("max_radius_px", p.max_radius_px, 1.0, 1000.0);
  v("min_valid_fraction", p.min_valid_fraction, 0.0, 1.0);
  v("shape_orientation", p.shape_orientation);
  v("min_projection_angle_deg", p.min_projection_angle_deg, 0.0, 90.0);
  v("gradient_orientation", p.gradient_orientation);
}

template <class V>
void visitFields(MatchParams& p, V&& v) {
  v("ratio", p.ratio, 1e-6, 1.0);
  v("cross_check", p.cross_check);
}

template <class V>
void visitFields(MotionParams& p, V&& v) {
  v("inlier_threshold", p.inlier_threshold, 1e-6, 100.0);
  v("max_iterations", p.max_iterations, 1, 10000000);
  v("confidence", p.confidence, 0.0, 1.0);
  v("min_inliers", p.min_inliers, 3, 1000000);
  v("seed", p.seed, 0u, 0xffffffffu);
}

template <class V>
void visitFields(OdometryParams& p, V&& v) {
  v("min_inliers", p.min_inliers, 3, 100000);
  v("keyframe_inliers", p.keyframe_inliers, 3, 100000);
  v("keyframe_translation", p.keyframe_translation, 0.0, 100.0);
  v("keyframe_rotation_deg", p.keyframe_rotation_deg, 0.0, 180.0);
  v("reprojection_huber", p.reprojection_huber, 0.0, 1.0);
  v("lost_variance", p.lost_variance, 1.0, 1e12);
}

// Calls v(section, params) for each section of RisasParams, with the section
// names of the parameter files.
template <class V>
void visitSections(RisasParams& p, V&& v) {
  v("geometry", p.geometry);
  v("detector", p.detector);
  v("descriptor", p.descriptor);
  v("match", p.match);
  v("motion", p.motion);
  v("odometry", p.odometry);
}

}  // namespace risas

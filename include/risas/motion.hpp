// Rigid motion between two frames from matched 3D points: RANSAC over
// minimal 3-point samples, each solved and finally refined by Umeyama's
// least-squares method.
#pragma once

#include "risas/params.hpp"

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <vector>

namespace risas {

struct MotionEstimate {
  bool valid = false;  // at least min_inliers agree
  // Maps points of the query frame into the train frame: p_train = T p_query
  // (the dataset's p1 = R pk + t with frame k as query and frame 1 as train).
  Eigen::Isometry3d train_T_query = Eigen::Isometry3d::Identity();
  std::vector<char> inliers;  // one per match
  int num_inliers = 0;
  double rmse = 0.0;  // of the inliers, metres
};

// matches index query_points (queryIdx) and train_points (trainIdx).
// Deterministic for a given seed. Throws InputError on an index out of range.
MotionEstimate estimateRigidMotion(const std::vector<cv::Point3f>& query_points,
                                   const std::vector<cv::Point3f>& train_points,
                                   const std::vector<cv::DMatch>& matches, const MotionParams& params = MotionParams());

}  // namespace risas

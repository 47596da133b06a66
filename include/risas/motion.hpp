// Rigid motion between two frames from matched 3D points: RANSAC over
// minimal 3-point samples, each solved and finally refined by Umeyama's
// least-squares method; optionally refined again on the inliers'
// reprojection errors (refineByReprojection), as visual odometry wants.
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

// Refines a motion on its inliers by minimising the reprojection error of
// the train points into the query frame (3D to 2D, the estimation rtabmap's
// odometry uses by default): the query points enter only through their
// bearings (x/z, y/z), the direction of the keypoint's ray, so that the
// query frame's depth noise, which lies along that ray and grows with z²,
// does not pull the motion. Gauss-Newton with Huber weights; `huber` in
// normalised image units (pixels / focal length: 0.004 is 2 px at 525 px).
// The inliers are kept; rmse becomes their 3D RMSE under the refined motion.
// An estimate that is not valid, with fewer than 3 usable inliers (in front
// of both cameras), or whose robust cost the refinement does not lower is
// returned unchanged. Throws InputError on an index out of range, a valid
// estimate whose inlier flags are not one per match, or a huber that is not
// positive and finite (the odometry's 0, "no refit", skips the call).
MotionEstimate refineByReprojection(const std::vector<cv::Point3f>& query_points,
                                    const std::vector<cv::Point3f>& train_points,
                                    const std::vector<cv::DMatch>& matches, const MotionEstimate& estimate,
                                    double huber);

}  // namespace risas

// What a visual-odometry user gets from a method's matches: the rigid motion
// RANSAC recovers from them, against the ground truth. The same RANSAC
// (risas::estimateRigidMotion with poseRecoveryRansac()) and the same refit
// (PoseRefit) for every method.
#pragma once

#include "risas/evaluation/metrics.hpp"
#include "risas/intrinsics.hpp"
#include "risas/motion.hpp"

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <vector>

namespace risas::eval {

struct PoseError {
  double rotation_deg;  // angle of R_truth^T R_estimate
  double alignment_m;   // median over the points of |T_estimate p - T_truth p|
};

// The error of `estimate` against `truth` (both ref_T_query), the alignment
// over `points` (query-frame points: the report's are sharedScene's).
// Infinite alignment when there are no points.
PoseError poseError(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth,
                    const std::vector<cv::Point3f>& points);

// The points a pair's poses are judged on, the same for every method: the
// query frame's scene that both cameras see. Every `step`-th query pixel
// with depth, back-projected, whose point ref_T_query moves inside the
// reference image (reference_depth's size) in front of the camera. Judged
// on a method's own keypoints instead, an estimate is measured where its
// matches are, which is where it fits best, and two methods' estimates of
// the same accuracy score apart (docs/evaluation.md, "The pose judged on
// the shared scene"). Depths: CV_32FC1 metres, NaN where missing.
std::vector<cv::Point3f> sharedScene(const cv::Mat& query_depth, const cv::Mat& reference_depth, const Intrinsics& K,
                                     const Eigen::Isometry3d& ref_T_query, int step = 4);

struct PoseRecovery {
  int matches = 0;         // at the ratio, the RANSAC's input
  bool estimated = false;  // RANSAC found at least min_inliers agreeing
  Eigen::Isometry3d estimate = Eigen::Isometry3d::Identity();  // ref_T_query found (identity when none)
  int inliers = 0;
  // How far the inliers' query points spread across their longest direction
  // (metres; 0 when nothing was estimated): inlierSpread.
  double inlier_spread_m = 0.0;
  PoseError error{INFINITY, INFINITY};  // infinite when nothing was estimated
  bool within(double degrees, double metres) const {
    return estimated && error.rotation_deg <= degrees && error.alignment_m <= metres;
  }
  // The report's two criteria: the pose recovered within 5 deg / 5 cm, and
  // closely, within 2 deg / 2 cm.
  bool recovered() const { return within(5.0, 0.05); }
  bool recoveredClosely() const { return within(2.0, 0.02); }
};

// The second principal standard deviation of the points: near 0 when they
// lie along a line (or in one place), about which a rotation fitted to them
// is then poorly determined, however many there are. 0 for fewer than 2.
double inlierSpread(const std::vector<cv::Point3f>& points);

// A check of a pose that needs no ground truth: the query frame's depth,
// moved by ref_T_query into the reference camera, against the reference
// frame's own. Of every `step`-th query pixel with depth that lands in the
// reference image on a pixel with depth, the share within `tolerance`
// metres of it. A pose off in tilt or along the view moves whole surfaces
// off and lowers it; what only one camera sees lowers it alike for every
// pose of a pair. NaN when no pixel lands. Depths: CV_32FC1 metres, NaN
// where missing (RgbdFrame::depth).
double depthAgreement(const cv::Mat& query_depth, const cv::Mat& reference_depth, const Intrinsics& K,
                      const Eigen::Isometry3d& ref_T_query, double tolerance = 0.05, int step = 2);

// What the RANSAC motion is finally fitted to. Umeyama: the inliers' 3D
// points of both frames (estimateRigidMotion's own least-squares fit; the
// protocol of the issues' figures). Reprojection: that motion refined on
// the reference points' reprojection errors in the query image
// (refineByReprojection with OdometryParams' default Huber width, as
// risas::Odometry refits), so that the query frame's depth enters only
// through RANSAC's choice of inliers.
enum class PoseRefit { Umeyama, Reprojection };

// RANSAC of the report: 3 cm inlier distance, a fixed seed, otherwise
// MotionParams' defaults. With `seed_index` k > 0 the same with the k-th
// further seed: the same matches, other random samples.
MotionParams poseRecoveryRansac(int seed_index = 0);

// The candidates with ratio <= `ratio` as matches, their rigid motion by
// RANSAC and `refit`, scored against ref_T_query over `judged_points`
// (poseError).
PoseRecovery recoverPose(const std::vector<Candidate>& candidates, double ratio,
                         const std::vector<cv::Point3f>& query_points,
                         const std::vector<cv::Point3f>& reference_points, const Eigen::Isometry3d& ref_T_query,
                         const std::vector<cv::Point3f>& judged_points,
                         const MotionParams& ransac = poseRecoveryRansac(), PoseRefit refit = PoseRefit::Umeyama);

// recoverPose once with each of the first `seeds` RANSAC seeds
// (poseRecoveryRansac(0 .. seeds - 1)), in that order. Where the inliers are
// few among the matches, whether RANSAC draws an all-inlier sample in time
// is luck; the seeds' outcomes show how much.
std::vector<PoseRecovery> recoverPoseOverSeeds(const std::vector<Candidate>& candidates, double ratio,
                                               const std::vector<cv::Point3f>& query_points,
                                               const std::vector<cv::Point3f>& reference_points,
                                               const Eigen::Isometry3d& ref_T_query,
                                               const std::vector<cv::Point3f>& judged_points, int seeds,
                                               PoseRefit refit = PoseRefit::Umeyama);

}  // namespace risas::eval

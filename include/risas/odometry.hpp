// RGB-D visual odometry on any features with 3D points (RISAS, or ORB with
// depth for comparison): each frame is matched against the current
// keyframe (NNDR), its motion found by RANSAC and refined on the inliers
// (estimateRigidMotion), and its pose chained onto the keyframe's.
//
//   risas::Odometry odometry(params.odometry, params.match, params.motion);
//   for (...) {
//     const risas::OdometryResult r = odometry.track(risas->extract(frame));
//     if (r.tracked) use(r.world_T_camera, r.covariance);
//   }
//
// The world frame is the first frame's camera (or the pose given to
// reset()). Conventions as rtabmap's odometry: a frame that cannot be
// tracked keeps the last pose (never a jump) and reports lost_variance on
// every axis; it becomes the new keyframe at that held pose if it has
// enough features (a recovery, counted), else the next frame that has them
// does. The motion across the gap is not measured: the trajectory goes on
// from the held pose. Deterministic for a given
// input (RANSAC's seed is fixed).
#pragma once

#include "risas/features.hpp"
#include "risas/params.hpp"

#include <Eigen/Geometry>

namespace risas {

struct OdometryResult {
  bool tracked = false;       // the pose was estimated from this frame
  bool new_keyframe = false;  // the frame is now the keyframe
  Eigen::Isometry3d world_T_camera = Eigen::Isometry3d::Identity();
  // Of world_T_camera, in the order (x, y, z, rotation about x, y, z), the
  // rotations as a small rotation of the world frame: nav_msgs/Odometry's
  // layout. The keyframes' covariances composed (composeCovariance) with
  // each increment's. lost_variance on the diagonal when not tracked.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  int matches = 0, inliers = 0;
  double rmse = 0.0;  // of the inliers, metres
  // The motion from the previous frame given to track() to this one
  // (motion_tracked), when this one was tracked and the previous one was
  // tracked or became the keyframe (a recovery's keyframe, whose held pose
  // is not measured, is where the next motion is measured from); not after
  // a lost frame or reset(). previous_T_camera, and its covariance in the
  // previous camera's axes, the convention below: what a twist is made of
  // (twist.hpp: twistFromMotion).
  bool motion_tracked = false;
  Eigen::Isometry3d previous_T_camera = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> motion_covariance = Eigen::Matrix<double, 6, 6>::Zero();
};

// Pose covariances here are of a pose T = (R, t) in (x, y, z, rotation
// about x, y, z) as nav_msgs/Odometry has them: the position perturbed in
// the reference frame's axes and the rotation by a small rotation of that
// frame, t + dt and exp(dtheta) R.

// The covariance of a rigid motion T = (R, t) fitted to inlier pairs
// q_i ~ R p_i + t with residual RMS `rmse`: rmse^2 (J^T J)^-1 over the
// point-to-point residuals, J_i = [I, -[R p_i]x], the convention above.
// Pass the rotated points R p_i (not q_i: a rotation of the target frame
// about its origin would move the position by dtheta x t as well). The
// inverse is taken of the regularised matrix, so that degenerate sets
// (collinear points) give large, finite variances.
Eigen::Matrix<double, 6, 6> motionCovariance(const std::vector<Eigen::Vector3d>& rotated_points, double rmse);

// A covariance in (x, y, z, rotation x, y, z) of frame A expressed in frame
// B, given R_BA: both blocks rotated, R C R^T with R = diag(R_BA, R_BA).
Eigen::Matrix<double, 6, 6> rotateCovariance(const Eigen::Matrix<double, 6, 6>& covariance, const Eigen::Matrix3d& R);

// The covariance of world_T_b = world_T_a * a_T_b to first order, the two
// independent: world_T_a's covariance (world axes) and a_T_b's (a's axes).
// world_T_a's rotational uncertainty moves b by its lever arm, the offset
// R_wa t_ab: J_a = [[I, -[R_wa t_ab]x], [0, I]], J_ab = diag(R_wa, R_wa).
// This is how a chain of keyframes turns heading uncertainty into position
// uncertainty that grows with the distance travelled.
Eigen::Matrix<double, 6, 6> composeCovariance(const Eigen::Isometry3d& world_T_a,
                                              const Eigen::Matrix<double, 6, 6>& covariance_a,
                                              const Eigen::Isometry3d& a_T_b,
                                              const Eigen::Matrix<double, 6, 6>& covariance_ab);

// The covariance of a_T_b = k_T_a^-1 * k_T_b (in a's axes) from the
// covariances of k_T_a and k_T_b (k's axes), their errors taken as
// independent: composeCovariance solved for a_T_b's. Two frames fitted to
// the same keyframe share its points' noise, so between them this
// overstates the motion's uncertainty by the part they have in common.
Eigen::Matrix<double, 6, 6> relativeCovariance(const Eigen::Isometry3d& k_T_a,
                                               const Eigen::Matrix<double, 6, 6>& covariance_a,
                                               const Eigen::Isometry3d& k_T_b,
                                               const Eigen::Matrix<double, 6, 6>& covariance_b);

class Odometry {
 public:
  Odometry(const OdometryParams& params = OdometryParams(), const MatchParams& match = MatchParams(),
           const MotionParams& motion = MotionParams());

  // The pose of this frame. features: descriptors (CV_32F or CV_8U) with
  // one geometry entry (3D point in the camera frame) per keypoint; rows
  // whose point is not finite are ignored. InputError when descriptors and
  // geometry differ in count, or the descriptors differ in type, width or
  // known layout (Features::descriptor_layout) from the keyframe's: after a
  // change of descriptor, reset() first.
  OdometryResult track(const Features& features);

  // Forget the keyframe; the next frame starts at world_T_camera.
  void reset(const Eigen::Isometry3d& world_T_camera = Eigen::Isometry3d::Identity());

  const Eigen::Isometry3d& pose() const { return pose_; }
  int frames() const { return frames_; }
  int lostFrames() const { return lost_frames_; }  // frames not tracked, since construction or reset
  int recoveries() const { return recoveries_; }   // re-initialisations after being lost
  int keyframes() const { return keyframes_; }
  bool lost() const { return lost_; }

 private:
  struct Keyframe {
    cv::Mat descriptors;
    std::string layout;  // Features::descriptor_layout
    std::vector<cv::Point3f> points;
    Eigen::Isometry3d world_T_camera = Eigen::Isometry3d::Identity();
    Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
    bool valid = false;
  };
  static Keyframe keyframeOf(const Features& features);
  void makeKeyframe(Keyframe keyframe, const Eigen::Isometry3d& pose, const Eigen::Matrix<double, 6, 6>& covariance);
  Eigen::Matrix<double, 6, 6> lostCovariance() const;
  // Remembers this frame as the one the next frame's motion is from.
  void rememberLast(bool tracked, const Eigen::Isometry3d& key_T_frame = Eigen::Isometry3d::Identity(),
                    const Eigen::Matrix<double, 6, 6>& covariance = Eigen::Matrix<double, 6, 6>::Zero());

  OdometryParams params_;
  MatchParams match_;
  MotionParams motion_;
  Keyframe keyframe_;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> covariance_ = Eigen::Matrix<double, 6, 6>::Zero();  // the last tracked frame's
  // The last frame given to track(), when it was tracked or made the
  // keyframe: its pose on the keyframe and that pose's covariance in the
  // keyframe's axes (identity and zero when it is the keyframe). The next
  // frame's motion is from it.
  bool last_tracked_ = false;
  Eigen::Isometry3d key_T_last_ = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> last_covariance_ = Eigen::Matrix<double, 6, 6>::Zero();
  bool lost_ = false;
  int frames_ = 0, lost_frames_ = 0, recoveries_ = 0, keyframes_ = 0;
};

}  // namespace risas

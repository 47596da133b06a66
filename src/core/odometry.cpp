#include "risas/odometry.hpp"

#include "risas/cross_product.hpp"
#include "risas/errors.hpp"
#include "risas/matcher.hpp"
#include "risas/motion.hpp"

#include <cmath>

namespace risas {
namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6>;

}  // namespace

Matrix6 rotateCovariance(const Matrix6& covariance, const Eigen::Matrix3d& R) {
  Matrix6 big = Matrix6::Zero();
  big.topLeftCorner<3, 3>() = R;
  big.bottomRightCorner<3, 3>() = R;
  return big * covariance * big.transpose();
}

Matrix6 composeCovariance(const Eigen::Isometry3d& world_T_a, const Matrix6& covariance_a,
                          const Eigen::Isometry3d& a_T_b, const Matrix6& covariance_ab) {
  Matrix6 J_a = Matrix6::Identity();
  J_a.topRightCorner<3, 3>() = -crossProductMatrix(world_T_a.linear() * a_T_b.translation());
  return J_a * covariance_a * J_a.transpose() + rotateCovariance(covariance_ab, world_T_a.linear());
}

Matrix6 relativeCovariance(const Eigen::Isometry3d& k_T_a, const Matrix6& covariance_a, const Eigen::Isometry3d& k_T_b,
                           const Matrix6& covariance_b) {
  // composeCovariance: d_b = J_a d_a + diag(R_ka, R_ka) d_ab, J_a's lever
  // arm R_ka t_ab = t_kb - t_ka; solved for d_ab.
  Matrix6 J_a = Matrix6::Identity();
  J_a.topRightCorner<3, 3>() = -crossProductMatrix(k_T_b.translation() - k_T_a.translation());
  return rotateCovariance(covariance_b + J_a * covariance_a * J_a.transpose(), k_T_a.linear().transpose());
}

Matrix6 motionCovariance(const std::vector<Eigen::Vector3d>& rotated_points, double rmse) {
  Matrix6 H = Matrix6::Zero();
  for (const Eigen::Vector3d& x : rotated_points) {
    Eigen::Matrix<double, 3, 6> J;
    J.leftCols<3>() = Eigen::Matrix3d::Identity();
    J.rightCols<3>() = -crossProductMatrix(x);
    H += J.transpose() * J;
  }
  // A floor on the noise (1 mm) keeps an exact fit from claiming certainty;
  // the regulariser keeps a degenerate set finite.
  const double sigma2 = std::max(rmse * rmse, 1e-6);
  return sigma2 * (H + 1e-9 * Matrix6::Identity()).inverse();
}

Odometry::Odometry(const OdometryParams& params, const MatchParams& match, const MotionParams& motion)
    : params_(params), match_(match), motion_(motion) {
  params_.validate();
  match_.validate();
  motion_.validate();
}

void Odometry::reset(const Eigen::Isometry3d& world_T_camera) {
  keyframe_ = Keyframe();
  pose_ = world_T_camera;
  covariance_.setZero();
  lost_ = false;
  rememberLast(false);
  frames_ = lost_frames_ = recoveries_ = keyframes_ = 0;
}

void Odometry::rememberLast(bool tracked, const Eigen::Isometry3d& key_T_frame, const Matrix6& covariance) {
  last_tracked_ = tracked;
  key_T_last_ = key_T_frame;
  last_covariance_ = covariance;
}

Odometry::Keyframe Odometry::keyframeOf(const Features& features) {
  const int n = static_cast<int>(features.keypoints.size());
  if (features.descriptors.rows != n || static_cast<int>(features.geometry.size()) != n) {
    throw InputError("odometry: features need one descriptor row and one 3D point per keypoint (" +
                     std::to_string(n) + " keypoints, " + std::to_string(features.descriptors.rows) +
                     " descriptors, " + std::to_string(features.geometry.size()) + " points)");
  }
  Keyframe k;
  k.layout = features.descriptor_layout;
  k.descriptors = cv::Mat(0, features.descriptors.cols, features.descriptors.type());
  for (int i = 0; i < n; ++i) {
    const cv::Point3f& p = features.geometry[static_cast<size_t>(i)].point;
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && p.z > 0.0f)) continue;
    k.points.push_back(p);
    k.descriptors.push_back(features.descriptors.row(i));
  }
  k.valid = true;
  return k;
}

void Odometry::makeKeyframe(Keyframe keyframe, const Eigen::Isometry3d& pose, const Matrix6& covariance) {
  keyframe.world_T_camera = pose;
  keyframe.covariance = covariance;
  keyframe_ = std::move(keyframe);
  ++keyframes_;
  rememberLast(true);  // the next frame's motion is from the keyframe itself
}

Matrix6 Odometry::lostCovariance() const { return params_.lost_variance * Matrix6::Identity(); }

OdometryResult Odometry::track(const Features& features) {
  Keyframe frame = keyframeOf(features);
  // Equal widths do not make descriptors comparable: the counts of other
  // bins would match, silently badly. (Type and width: matchDescriptors.)
  if (keyframe_.valid && !layoutsAgree(frame.layout, keyframe_.layout)) {
    throw InputError("odometry: descriptors of layout '" + frame.layout + "' cannot be matched with the keyframe's ('" +
                     keyframe_.layout + "'); reset() after changing the descriptor");
  }
  ++frames_;
  OdometryResult r;
  r.world_T_camera = pose_;
  const int enough = std::max(params_.min_inliers, motion_.min_inliers);

  if (!keyframe_.valid) {
    // The first frame (or the first after a lost one too poor to start
    // from) starts at the current pose if it has the features to be tracked
    // against. The first defines the origin and counts as tracked; after
    // being lost the motion across the gap is unmeasured, the pose is held,
    // and the covariance goes on from the last tracked one (it cannot count
    // what it did not see).
    const bool first = !lost_;
    if (static_cast<int>(frame.points.size()) < enough) {
      ++lost_frames_;
      rememberLast(false);
      r.covariance = lostCovariance();
      return r;
    }
    if (!first) ++recoveries_;
    makeKeyframe(std::move(frame), pose_, covariance_);
    lost_ = false;
    r.new_keyframe = true;
    r.tracked = first;
    r.covariance = first ? covariance_ : lostCovariance();
    if (!first) ++lost_frames_;
    return r;
  }

  const std::vector<cv::DMatch> matches = matchDescriptors(frame.descriptors, keyframe_.descriptors, match_);
  MotionEstimate m = estimateRigidMotion(frame.points, keyframe_.points, matches, motion_);
  if (params_.reprojection_huber > 0.0) {
    m = refineByReprojection(frame.points, keyframe_.points, matches, m, params_.reprojection_huber);
  }
  r.matches = static_cast<int>(matches.size());
  r.inliers = m.num_inliers;
  r.rmse = m.rmse;
  if (!m.valid || m.num_inliers < enough) {
    // Lost. The pose is held; this frame, if it has the features, is the
    // new keyframe at the held pose (a recovery), so that the next frame can
    // be tracked again. Otherwise the next frame that has them starts anew.
    lost_ = true;
    ++lost_frames_;
    rememberLast(false);
    r.covariance = lostCovariance();
    if (static_cast<int>(frame.points.size()) >= enough) {
      ++recoveries_;
      makeKeyframe(std::move(frame), pose_, covariance_);
      r.new_keyframe = true;
    } else {
      keyframe_ = Keyframe();
    }
    return r;
  }

  const Eigen::Isometry3d& key_T_frame = m.train_T_query;
  std::vector<Eigen::Vector3d> rotated_points;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (!m.inliers[i]) continue;
    const cv::Point3f& p = frame.points[static_cast<size_t>(matches[i].queryIdx)];
    rotated_points.push_back(key_T_frame.linear() * Eigen::Vector3d(p.x, p.y, p.z));
  }
  // The increment's covariance, in the keyframe's camera frame, composed
  // with the keyframe's own.
  const Matrix6 increment = motionCovariance(rotated_points, m.rmse);
  pose_ = keyframe_.world_T_camera * key_T_frame;
  r.tracked = true;
  r.world_T_camera = pose_;
  r.covariance = composeCovariance(keyframe_.world_T_camera, keyframe_.covariance, key_T_frame, increment);
  covariance_ = r.covariance;
  if (last_tracked_) {
    r.motion_tracked = true;
    r.previous_T_camera = key_T_last_.inverse() * key_T_frame;
    r.motion_covariance = relativeCovariance(key_T_last_, last_covariance_, key_T_frame, increment);
  }

  const double moved = key_T_frame.translation().norm();
  const double turned = Eigen::AngleAxisd(key_T_frame.linear()).angle() * 180.0 / M_PI;
  lost_ = false;
  if (m.num_inliers < params_.keyframe_inliers || moved > params_.keyframe_translation ||
      turned > params_.keyframe_rotation_deg) {
    makeKeyframe(std::move(frame), pose_, r.covariance);
    r.new_keyframe = true;
  } else {
    rememberLast(true, key_T_frame, increment);
  }
  return r;
}

}  // namespace risas

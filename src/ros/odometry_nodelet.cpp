// risas/OdometryNodelet: visual odometry from risas/KeypointArray alone (the
// message is enough: descriptors and 3D points), risas::Odometry inside.
// Conventions as rtabmap_ros's rgbd_odometry:
//   in   keypoints   risas/KeypointArray
//   out  odom        nav_msgs/Odometry, header.frame_id ~odom_frame_id
//                    (odom), child_frame_id the camera frame, or
//                    ~base_frame_id when given (then the base's pose,
//                    through the static tf base -> camera); while lost the
//                    held pose with ~odometry/lost_variance on the diagonal,
//                    never a jump
//        odom_path   nav_msgs/Path of the poses, for rviz (~path_length)
//        tf          ~odom_frame_id -> child, when ~publish_tf (true)
//   srv  ~reset      std_srvs/Empty: back to identity, path cleared
// It follows the camera frame of the first array (after a start or a
// reset) and skips arrays of another, with an error.
// Parameters of the odometry, matching and RANSAC as in config/risas.yaml
// (~odometry/min_inliers, ~match/ratio, ~motion/inlier_threshold, ...).
#include "risas/errors.hpp"
#include "risas/odometry.hpp"
#include "risas/ros/conversions.hpp"
#include "risas/ros/log_throttle.hpp"
#include "risas/ros/node_params.hpp"

#include <risas/KeypointArray.h>

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <std_srvs/Empty.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <memory>
#include <mutex>
#include <optional>

namespace risas_ros {

class OdometryNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    try {
      NodeParams params(pnh);
      params_ = params.risas();
      odom_frame_ = params.frameId("odom_frame_id", "odom");
      base_frame_ = params.frameId("base_frame_id", "");  // not set: the camera's pose
      requireDistinctFrames({{"~odom_frame_id", odom_frame_}, {"~base_frame_id", base_frame_}});
      publish_tf_ = params.flag("publish_tf", true);
      path_length_ = params.whole("path_length", 10000, 0, 10000000);
      params.refuseUnread();
    } catch (const std::exception& e) {
      NODELET_FATAL("odometry parameters rejected: %s", e.what());
      throw;
    }
    odometry_ = std::make_unique<risas::Odometry>(params_.odometry, params_.match, params_.motion);
    if (!base_frame_.empty()) {
      tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
      tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
    }
    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 10);
    path_pub_ = nh.advertise<nav_msgs::Path>("odom_path", 1, true);
    reset_srv_ = pnh.advertiseService("reset", &OdometryNodelet::onReset, this);
    sub_ = nh.subscribe("keypoints", 10, &OdometryNodelet::onKeypoints, this);
  }

  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    std::lock_guard<std::mutex> lock(mutex_);
    restart();
    camera_frame_.clear();  // the next array's camera is followed
    base_T_camera_.reset();
    NODELET_INFO("odometry reset to identity");
    return true;
  }

  // The odometry at identity with a new keyframe, its path empty, and no
  // previous stamp to take a twist's time from. Called under mutex_.
  void restart() {
    odometry_->reset();
    path_.poses.clear();
    last_stamp_.reset();
  }

  // base_T_camera from tf (static), once it is known.
  std::optional<Eigen::Isometry3d> baseTCamera(const std::string& camera_frame) {
    if (base_T_camera_) return base_T_camera_;
    try {
      base_T_camera_ = fromTransform(tf_buffer_->lookupTransform(base_frame_, camera_frame, ros::Time(0)).transform);
    } catch (const tf2::TransformException& e) {
      if (errors_.shouldLog("no tf")) {
        NODELET_WARN("odometry waits for tf %s -> %s: %s", base_frame_.c_str(), camera_frame.c_str(), e.what());
      }
    }
    return base_T_camera_;
  }

  void onKeypoints(const risas::KeypointArrayConstPtr& message) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string& camera_frame = message->header.frame_id;
    if (!isTfFrameId(camera_frame)) {  // it becomes the child frame on tf
      if (errors_.shouldLog("frame_id")) {
        NODELET_ERROR("skipping KeypointArray: header.frame_id '%s' is not %s", camera_frame.c_str(), kTfFrameIdRule);
      }
      return;
    }
    if (camera_frame == odom_frame_) {
      if (errors_.shouldLog("odom frame")) {
        NODELET_ERROR("skipping KeypointArray: its camera frame is ~odom_frame_id '%s', which cannot be its own "
                      "parent",
                      odom_frame_.c_str());
      }
      return;
    }
    // One odometry follows one camera: another camera's arrays on the same
    // topic would be matched against this one's keyframe, and moved by its
    // tf to the base. Checked before the stamps, so that another camera's
    // earlier stamps do not restart the odometry.
    if (camera_frame_.empty()) camera_frame_ = camera_frame;
    if (camera_frame != camera_frame_) {
      if (errors_.shouldLog("camera")) {
        NODELET_ERROR("skipping KeypointArray of camera frame '%s': this odometry follows '%s' (~reset follows the "
                      "next array's)",
                      camera_frame.c_str(), camera_frame_.c_str());
      }
      return;
    }
    // A stamp before the last one tracked is another recording, or the same
    // bag played again (rosbag play --loop): the odometry starts anew, as
    // from ~reset, rather than chaining the new start onto the old end.
    if (last_stamp_ && message->header.stamp < *last_stamp_) {
      NODELET_INFO("KeypointArray stamped %.3f s before the previous one (a bag played again?): odometry reset to "
                   "identity",
                   secondsBetween(*last_stamp_, message->header.stamp));
      restart();
    }
    std::optional<Eigen::Isometry3d> base_T_camera = Eigen::Isometry3d::Identity();
    if (!base_frame_.empty() && !(base_T_camera = baseTCamera(camera_frame))) return;

    risas::OdometryResult r;
    try {
      const risas::Features features = fromMessage(*message);
      // A reconfigured descriptor (its size, or its layout at the same size)
      // cannot be matched with the keyframe's.
      const std::string descriptor =
          std::to_string(message->descriptor_dim) + "-d, layout '" + message->descriptor_layout + "'";
      if (last_descriptor_ && *last_descriptor_ != descriptor) {
        NODELET_INFO("descriptor changed (%s -> %s): odometry starts a new keyframe at the current pose",
                     last_descriptor_->c_str(), descriptor.c_str());
        odometry_->reset(odometry_->pose());
      }
      last_descriptor_ = descriptor;
      r = odometry_->track(features);
    } catch (const risas::InputError& e) {
      if (errors_.shouldLog(e.what())) NODELET_ERROR("skipping KeypointArray: %s", e.what());
      return;
    }
    // The twist's time: from the previous message the odometry tracked.
    const double dt = last_stamp_ ? secondsBetween(message->header.stamp, *last_stamp_) : 0.0;
    last_stamp_ = message->header.stamp;
    if (r.motion_tracked && dt <= 0.0 && errors_.shouldLog("stamps")) {
      NODELET_WARN("KeypointArray stamped as the previous one: no twist for this frame");
    }
    if (!r.tracked && errors_.shouldLog("lost")) {
      NODELET_WARN("odometry lost: %d inliers of %d matches (%d frames lost, %d recoveries so far); holding the pose",
                   r.inliers, r.matches, odometry_->lostFrames(), odometry_->recoveries());
    }

    // In the odom frame: the camera, or the base through the static tf.
    const std::string child = base_frame_.empty() ? camera_frame : base_frame_;
    std_msgs::Header header;
    header.stamp = message->header.stamp;
    header.frame_id = odom_frame_;
    const nav_msgs::Odometry odom = toOdometry(r, header, child, *base_T_camera, params_.odometry.lost_variance, dt);
    odom_pub_.publish(odom);

    if (publish_tf_) {
      geometry_msgs::TransformStamped t;
      t.header = odom.header;
      t.child_frame_id = child;
      t.transform.translation.x = odom.pose.pose.position.x;
      t.transform.translation.y = odom.pose.pose.position.y;
      t.transform.translation.z = odom.pose.pose.position.z;
      t.transform.rotation = odom.pose.pose.orientation;
      tf_broadcaster_.sendTransform(t);
    }
    geometry_msgs::PoseStamped stamped;
    stamped.header = odom.header;
    stamped.pose = odom.pose.pose;
    path_.header = odom.header;
    path_.poses.push_back(stamped);
    if (static_cast<int>(path_.poses.size()) > path_length_) path_.poses.erase(path_.poses.begin());
    path_pub_.publish(path_);
  }

  std::mutex mutex_;
  risas::RisasParams params_;
  std::unique_ptr<risas::Odometry> odometry_;
  std::string odom_frame_, base_frame_;
  bool publish_tf_ = true;
  int path_length_ = 10000;
  std::optional<std::string> last_descriptor_;  // the last message's descriptor size and layout
  std::string camera_frame_;  // of the arrays followed; empty until the first after a start or ~reset
  std::optional<Eigen::Isometry3d> base_T_camera_;  // of camera_frame_
  std::optional<ros::Time> last_stamp_;  // of the last message given to the odometry
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  ros::Publisher odom_pub_, path_pub_;
  ros::ServiceServer reset_srv_;
  ros::Subscriber sub_;
  nav_msgs::Path path_;
  LogThrottle errors_{5.0};
};

}  // namespace risas_ros

PLUGINLIB_EXPORT_CLASS(risas_ros::OdometryNodelet, nodelet::Nodelet)

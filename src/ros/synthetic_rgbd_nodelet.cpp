// risas/SyntheticRgbdNodelet: a rendered RGB-D camera for the demo and the
// tests, no hardware needed. A 640x480 camera swings back and forth on an arc
// around the synthetic scene and publishes, like an OpenNI camera does,
//   rgb/image_rect_color        bgr8
//   depth_registered/image_raw  16UC1 millimetres, registered to rgb
//   rgb/camera_info
// plus its true pose as tf ~world_frame -> ~truth_frame_id: a frame of its
// own, as simulators publish ground truth, so that an odometry can parent the
// camera frame itself. It renders only while someone subscribes. Parameters:
// ~rate (Hz, 30), ~frame_id (camera_rgb_optical_frame), ~world_frame (world),
// ~truth_frame_id (~frame_id + "_truth"), ~arc_deg (swing amplitude, 25),
// ~period (seconds per swing, 12).
#include "risas/ros/conversions.hpp"
#include "risas/ros/node_params.hpp"
#include "risas/synthetic_scene.hpp"

#include <cv_bridge/cv_bridge.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/image_encodings.h>
#include <tf2_ros/transform_broadcaster.h>

#include <cmath>
#include <memory>

namespace risas_ros {

using risas::SyntheticRender;
using risas::SyntheticScene;

class SyntheticRgbdNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    double rate = 30.0;
    try {
      NodeParams params(pnh);
      rate = params.number("rate", 30.0, 0.01, 1000.0);
      frame_id_ = params.frameId("frame_id", "camera_rgb_optical_frame");
      world_frame_ = params.frameId("world_frame", "world");
      truth_frame_ = params.frameId("truth_frame_id", frame_id_ + "_truth");
      requireDistinctFrames({{"~frame_id", frame_id_}, {"~world_frame", world_frame_}, {"~truth_frame_id", truth_frame_}});
      arc_ = params.number("arc_deg", 25.0, 0.0, 180.0) * M_PI / 180.0;
      period_ = params.number("period", 12.0, 0.01, 1e6);
      params.refuseUnread();
    } catch (const std::invalid_argument& e) {
      NODELET_FATAL("invalid synthetic camera parameter: %s", e.what());
      throw;
    }

    info_ = cameraInfoFromIntrinsics(risas::syntheticIntrinsics(), size_);
    info_.header.frame_id = frame_id_;
    image_transport::ImageTransport it(nh);
    pub_rgb_ = it.advertise("rgb/image_rect_color", 5);
    pub_depth_ = it.advertise("depth_registered/image_raw", 5);
    pub_info_ = nh.advertise<sensor_msgs::CameraInfo>("rgb/camera_info", 5);
    start_ = ros::Time::now();
    timer_ = nh.createTimer(ros::Duration(1.0 / rate), [this](const ros::TimerEvent&) { tick(); });
  }

  void tick() {
    if (pub_rgb_.getNumSubscribers() == 0 && pub_depth_.getNumSubscribers() == 0 && pub_info_.getNumSubscribers() == 0) {
      return;
    }
    const ros::Time stamp = ros::Time::now();
    const double t = (stamp - start_).toSec();
    const Eigen::Isometry3d world_T_camera = SyntheticScene::demoCamera(arc_ * std::sin(2.0 * M_PI * t / period_));
    const SyntheticRender render = scene_.render(risas::syntheticIntrinsics(), size_, world_T_camera);

    std_msgs::Header header;
    header.stamp = stamp;
    header.frame_id = frame_id_;
    geometry_msgs::TransformStamped pose;
    pose.header.stamp = stamp;
    pose.header.frame_id = world_frame_;
    pose.child_frame_id = truth_frame_;
    pose.transform = toTransform(world_T_camera);
    tf_.sendTransform(pose);  // first, so the pose is known when the images arrive
    auto info = boost::make_shared<sensor_msgs::CameraInfo>(info_);
    info->header = header;
    pub_rgb_.publish(cv_bridge::CvImage(header, sensor_msgs::image_encodings::BGR8, render.bgr).toImageMsg());
    pub_depth_.publish(cv_bridge::CvImage(header, sensor_msgs::image_encodings::TYPE_16UC1, render.depth_mm).toImageMsg());
    pub_info_.publish(info);
  }

  const SyntheticScene scene_ = SyntheticScene::demo();
  const cv::Size size_{640, 480};
  std::string frame_id_, world_frame_, truth_frame_;
  double arc_ = 0.0, period_ = 1.0;
  sensor_msgs::CameraInfo info_;
  image_transport::Publisher pub_rgb_, pub_depth_;
  ros::Publisher pub_info_;
  tf2_ros::TransformBroadcaster tf_;
  ros::Time start_;
  ros::Timer timer_;
};

}  // namespace risas_ros

PLUGINLIB_EXPORT_CLASS(risas_ros::SyntheticRgbdNodelet, nodelet::Nodelet)

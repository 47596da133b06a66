// Between ROS messages and the core library's types. The ROS layer's only
// logic besides wiring: every check of an incoming message lives here, where
// it is unit-tested without a ROS master.
#pragma once

#include "risas/features.hpp"
#include "risas/intrinsics.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <risas/KeypointArray.h>

#include <ros/node_handle.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <Eigen/Geometry>
#include <geometry_msgs/Transform.h>

namespace risas_ros {

using risas::Features;
using risas::Intrinsics;
using risas::KeypointArray;
using risas::KeypointArrayPtr;
using risas::RgbdFrame;
using risas::RisasParams;

// K of a CameraInfo (the rectified image's intrinsics); InputError when K is
// all zero (an uncalibrated camera) or not a pinhole matrix.
Intrinsics intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info);
sensor_msgs::CameraInfo cameraInfoFromIntrinsics(const Intrinsics& intrinsics, cv::Size size);

// A validated frame from registered colour (rgb8, bgr8, rgba8, bgra8, mono8)
// and depth (16UC1 millimetres, 32FC1 metres) with their CameraInfo. Shares
// the messages' pixel buffers where it can. InputError, naming the problem,
// on another encoding, a size mismatch between the images or with the
// CameraInfo, differing frame_ids (the depth is not registered to the colour
// image), or bad intrinsics.
RgbdFrame frameFromMessages(const sensor_msgs::Image& color, const sensor_msgs::Image& depth,
                            const sensor_msgs::CameraInfo& info);

KeypointArrayPtr toMessage(const Features& features, const std_msgs::Header& header,
                           const sensor_msgs::CameraInfo& info);
// The inverse; descriptors are copied out of the message. InputError when the
// descriptor array does not hold keypoints.size() x descriptor_dim values.
Features fromMessage(const KeypointArray& message);

geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T);
// The inverse: the quaternion normalised.
Eigen::Isometry3d fromTransform(const geometry_msgs::Transform& t);

// RisasParams from the parameter server, nested as in config/risas.yaml
// (~detector/tau, ~descriptor/n_bin, ...); absent values keep their defaults.
// std::invalid_argument when a value is out of range.
RisasParams paramsFromServer(const ros::NodeHandle& nh);

}  // namespace risas_ros

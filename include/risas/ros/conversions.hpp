// Between ROS messages and the core library's types. The ROS layer's only
// logic besides wiring: every check of an incoming message lives here, where
// it is unit-tested without a ROS master.
#pragma once

#include "risas/features.hpp"
#include "risas/intrinsics.hpp"
#include "risas/odometry.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <risas/KeypointArray.h>

#include <ros/node_handle.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <Eigen/Geometry>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <nav_msgs/Odometry.h>
#include <std_msgs/Header.h>

#include <string>
#include <vector>

namespace risas_ros {

using risas::Features;
using risas::Intrinsics;
using risas::KeypointArray;
using risas::KeypointArrayPtr;
using risas::RgbdFrame;
using risas::RisasParams;

// The rectified image's intrinsics: the projection P, read as
// image_geometry::PinholeCameraModel reads it (it differs from K whenever the
// camera was calibrated with distortion), for the image as published: with
// binning and roi applied (image_proc's crop_decimate, reduced driver
// modes). K when P is all zero (drivers that fill only K). InputError when
// both are all zero (an uncalibrated camera) or P's left 3x3 is no pinhole
// matrix.
Intrinsics intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info);
sensor_msgs::CameraInfo cameraInfoFromIntrinsics(const Intrinsics& intrinsics, cv::Size size);

// A validated frame from registered colour (rgb8, bgr8, rgba8, bgra8, mono8)
// and depth (16UC1 millimetres, 32FC1 metres) with their CameraInfo. Shares
// the messages' pixel buffers where it can. InputError, naming the problem,
// on another encoding, a size mismatch between the images or with the
// CameraInfo (its size after binning and roi), differing frame_ids (the
// depth is not registered to the colour image, or the CameraInfo, when it
// names a frame, is another camera's), or bad intrinsics.
RgbdFrame frameFromMessages(const sensor_msgs::Image& color, const sensor_msgs::Image& depth,
                            const sensor_msgs::CameraInfo& info);

// later - earlier, in seconds. ros::Time's own difference throws
// std::runtime_error for stamps more than 2^31 s apart (a stamp of zero
// against one beyond 2038, an uninitialised or corrupt one in a bag), and a
// node must not die of a stamp.
double secondsBetween(const ros::Time& later, const ros::Time& earlier);

// Whether colour and depth show one moment. An ApproximateTime synchroniser
// pairs the nearest messages it holds however far apart they are, and depth
// of another moment puts a moving camera's points where they were then.
// InputError when the stamps lie more than max_interval seconds apart (0: no
// bound, as depth_image_proc and rtabmap's default); else a warning's text
// when they lie more than kOneMomentInterval apart, and "" when within it.
inline constexpr double kOneMomentInterval = 0.02;  // s: the TUM association's tolerance, rtabmap's warning's
std::string checkOneMoment(const std_msgs::Header& color, const std_msgs::Header& depth, double max_interval);

KeypointArrayPtr toMessage(const Features& features, const std_msgs::Header& header,
                           const sensor_msgs::CameraInfo& info);
// The keypoints' 3D points for rviz and PCL: an unordered cloud (height 1)
// with float32 fields x, y, z (metres, camera optical frame), response, and
// normal_x, normal_y, normal_z (unit, facing the camera), in PCL's names
// (pcl::PointXYZ... + pcl::Normal). Keypoints without geometry are left out.
sensor_msgs::PointCloud2Ptr toPointCloud(const Features& features, const std_msgs::Header& header);

// The inverse; descriptors are copied out of the message. InputError when the
// descriptor array does not hold keypoints.size() x descriptor_dim values,
// or a keypoint's pixel or descriptor is not finite. A NaN 3D point is kept:
// a keypoint without depth, which risas::Odometry skips.
Features fromMessage(const KeypointArray& message);

geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T);
geometry_msgs::Pose toPose(const Eigen::Isometry3d& T);
// The inverse: the quaternion normalised.
Eigen::Isometry3d fromTransform(const geometry_msgs::Transform& t);

// The odometry's result as nav_msgs/Odometry. header: the stamp and the
// odom frame; base_T_camera: the camera's static pose on child_frame_id
// (identity when the child is the camera itself). The pose published is
// base_T_camera * world_T_camera * camera_T_base (odom is the base at the
// start); its covariance, when tracked, is the camera's carried over the
// camera's offset by its rotational uncertainty (risas::composeCovariance)
// and turned into odom's axes, in nav_msgs's order (x, y, z, rotation about
// x, y, z); when lost, the result's own (lost_variance on the diagonal).
// The twist, child_frame_id's velocity in its own axes (nav_msgs's), is the
// result's motion from the previous frame over dt seconds
// (risas::twistFromMotion, carried to the base by risas::transformTwist)
// when the result has one (motion_tracked) and dt is a time between two
// frames (risas::isTwistInterval); otherwise zero
// with lost_variance on its diagonal.
nav_msgs::Odometry toOdometry(const risas::OdometryResult& result, const std_msgs::Header& header,
                              const std::string& child_frame_id, const Eigen::Isometry3d& base_T_camera,
                              double lost_variance, double dt);

// Checks the image_transport `transport` named by the parameter ~`parameter`
// against image_transport's loadable transports (`loadable`, as
// ImageTransport::getLoadableTransports() gives them: "image_transport/raw",
// "compressed_depth_image_transport/compressedDepth", ...). For depth, lossy
// transports (compressed, theora, ffmpeg, h264, h265) are refused: their
// codecs change depth values. std::invalid_argument, one line naming the
// transport and what is installed, otherwise.
void checkImageTransport(const std::string& transport, const std::string& parameter, bool depth,
                         const std::vector<std::string>& loadable);

// RisasParams from the parameter server, nested as in config/risas.yaml
// (~detector/tau, ~descriptor/n_bin, ...); absent values keep their defaults.
// The rules of a parameter file hold (RisasParams::read): flags are true,
// false, 0 or 1 (rosparam loads the shipped files' 0 and 1 as ints), whole
// numbers take no fraction, and std::invalid_argument names the first field
// that is unknown within a section (a typo), not a number, or out of range.
RisasParams paramsFromServer(const ros::NodeHandle& nh);

// The same from the sections as the server gives them: `sections` maps
// section names (detector, ...) to their structs; other names are not
// looked at (the private namespace holds the nodes' own parameters too).
RisasParams paramsFromXmlRpc(XmlRpc::XmlRpcValue& sections);

}  // namespace risas_ros

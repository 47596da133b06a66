// What the camera nodelet does with a device, without ROS plumbing: apply
// registration and sync, start and stop the streams, and turn frames into
// the messages an OpenNI camera publishes, with ROS stamps and frame_ids.
#pragma once

#include "risas/ros/rgbd_device.hpp"

#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace risas_ros {

struct CameraSettings {
  StreamMode mode;                   // VGA at 30 Hz
  bool depth_registration = true;    // IMAGE_REGISTRATION_DEPTH_TO_COLOR
  bool frame_sync = true;            // depth and colour frames of one instant
  std::string rgb_frame_id = "camera_rgb_optical_frame";
  std::string depth_frame_id = "camera_depth_optical_frame";  // unregistered depth only
};

struct CameraMessages {
  sensor_msgs::ImagePtr color;  // rgb8
  sensor_msgs::ImagePtr depth;  // 16UC1 millimetres
};

class RgbdCameraDriver {
 public:
  using Clock = std::function<ros::Time()>;

  // Applies registration and frame sync. Registration the device does not
  // support leaves depth unregistered (registered() false, and a warning()).
  // DeviceError when the device refuses a setting or the mode is invalid.
  RgbdCameraDriver(std::unique_ptr<RgbdDevice> device, const CameraSettings& settings, Clock clock);

  bool registered() const { return registered_; }
  const std::string& warning() const { return warning_; }
  const CameraSettings& settings() const { return settings_; }
  const RgbdDevice& device() const { return *device_; }
  // Depth goes to depth_registered/image_raw when registered, else depth/image_raw.
  std::string depthTopic() const { return registered_ ? "depth_registered/image_raw" : "depth/image_raw"; }

  void start();
  void stop();
  bool streaming() const { return streaming_; }

  // The next pair as messages, or none after timeout_s. Stamps follow the
  // device clock, anchored to ROS time at the first frame and re-anchored when
  // they drift more than 50 ms from it; colour and depth of one pair share
  // the colour frame's stamp when registered and synced. DeviceError when the
  // device is gone.
  std::optional<CameraMessages> next(double timeout_s);

  // Pinhole intrinsics from the colour camera's fields of view, principal
  // point in the image centre (what a device reports without calibration).
  sensor_msgs::CameraInfo cameraInfoFromFov() const;

  // A calibration (camera_info_manager's) for this mode: as it is when it
  // was made at the mode's size; with binning_x and binning_y k when the
  // mode is its size divided by a whole k (a 640x480 calibration in the
  // 320x240 mode), which image_geometry and risas read as the reduced
  // image's intrinsics; none for any other size (the caller falls back to
  // cameraInfoFromFov, as openni2_camera does).
  std::optional<sensor_msgs::CameraInfo> cameraInfoFromCalibration(const sensor_msgs::CameraInfo& calibration) const;

 private:
  ros::Time stampOf(uint64_t device_us);

  std::unique_ptr<RgbdDevice> device_;
  CameraSettings settings_;
  Clock clock_;
  bool registered_ = false;
  bool streaming_ = false;
  std::string warning_;
  std::optional<std::pair<ros::Time, uint64_t>> anchor_;  // ROS time at a device time
};

}  // namespace risas_ros

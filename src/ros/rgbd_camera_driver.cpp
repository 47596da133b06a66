#include "risas/ros/rgbd_camera_driver.hpp"

#include "risas/ros/conversions.hpp"

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/image_encodings.h>

#include <cmath>

namespace risas_ros {

RgbdCameraDriver::RgbdCameraDriver(std::unique_ptr<RgbdDevice> device, const CameraSettings& settings, Clock clock)
    : device_(std::move(device)), settings_(settings), clock_(std::move(clock)) {
  const StreamMode& m = settings_.mode;
  if (m.width <= 0 || m.height <= 0 || m.fps <= 0) {
    throw DeviceError("invalid stream mode " + std::to_string(m.width) + "x" + std::to_string(m.height) + "@" +
                      std::to_string(m.fps));
  }
  if (settings_.depth_registration && !device_->supportsRegistration()) {
    warning_ = device_->description() + " cannot register depth to colour: depth is published unregistered on " +
               "depth/image_raw in " + settings_.depth_frame_id;
  }
  registered_ = settings_.depth_registration && device_->supportsRegistration();
  device_->setRegistration(registered_);
  device_->setFrameSync(settings_.frame_sync);
}

void RgbdCameraDriver::start() {
  if (streaming_) return;
  device_->start(settings_.mode);
  anchor_.reset();
  streaming_ = true;
}

void RgbdCameraDriver::stop() {
  if (!streaming_) return;
  device_->stop();
  streaming_ = false;
}

ros::Time RgbdCameraDriver::stampOf(uint64_t device_us) {
  const ros::Time now = clock_();
  if (anchor_) {
    // Compared in seconds first: a device clock that jumps (reset, or a
    // garbage value) lies beyond ros::Duration's range, which would throw.
    const double since = static_cast<double>(static_cast<int64_t>(device_us - anchor_->second)) * 1e-6;
    if (std::abs(anchor_->first.toSec() + since - now.toSec()) <= 0.05) return anchor_->first + ros::Duration(since);
  }
  anchor_ = std::make_pair(now, device_us);
  return now;
}

std::optional<CameraMessages> RgbdCameraDriver::next(double timeout_s) {
  if (!streaming_) return std::nullopt;
  DeviceFrame color, depth;
  if (!device_->read(color, depth, timeout_s)) return std::nullopt;
  if (color.image.type() != CV_8UC3 || depth.image.type() != CV_16UC1) {
    throw DeviceError(device_->description() + " delivered frames of unexpected type " +
                      cv::typeToString(color.image.type()) + " / " + cv::typeToString(depth.image.type()));
  }
  std_msgs::Header color_header, depth_header;
  color_header.stamp = stampOf(color.timestamp_us);
  color_header.frame_id = settings_.rgb_frame_id;
  const bool same_instant = registered_ && settings_.frame_sync;
  depth_header.stamp = same_instant ? color_header.stamp : stampOf(depth.timestamp_us);
  depth_header.frame_id = registered_ ? settings_.rgb_frame_id : settings_.depth_frame_id;
  return CameraMessages{
      cv_bridge::CvImage(color_header, sensor_msgs::image_encodings::RGB8, color.image).toImageMsg(),
      cv_bridge::CvImage(depth_header, sensor_msgs::image_encodings::TYPE_16UC1, depth.image).toImageMsg()};
}

sensor_msgs::CameraInfo RgbdCameraDriver::cameraInfoFromFov() const {
  const double w = settings_.mode.width, h = settings_.mode.height;
  const risas::Intrinsics K(0.5 * w / std::tan(0.5 * device_->horizontalFov()),
                            0.5 * h / std::tan(0.5 * device_->verticalFov()), 0.5 * (w - 1.0), 0.5 * (h - 1.0));
  sensor_msgs::CameraInfo info = cameraInfoFromIntrinsics(K, cv::Size(settings_.mode.width, settings_.mode.height));
  info.header.frame_id = settings_.rgb_frame_id;
  return info;
}

std::optional<sensor_msgs::CameraInfo> RgbdCameraDriver::cameraInfoFromCalibration(
    const sensor_msgs::CameraInfo& calibration) const {
  const uint32_t w = static_cast<uint32_t>(settings_.mode.width), h = static_cast<uint32_t>(settings_.mode.height);
  if (w == 0 || h == 0 || calibration.width % w != 0 || calibration.height % h != 0) return std::nullopt;
  const uint32_t k = calibration.width / w;
  if (k == 0 || calibration.height / h != k) return std::nullopt;
  sensor_msgs::CameraInfo info = calibration;
  info.binning_x = info.binning_y = k == 1 ? 0 : k;  // 0: no binning, as drivers leave it
  info.header.frame_id = settings_.rgb_frame_id;
  return info;
}

}  // namespace risas_ros

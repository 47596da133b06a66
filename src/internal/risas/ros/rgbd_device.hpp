// The small interface between the camera nodelet and an RGB-D device, so
// that the nodelet's logic is tested with a fake device and no hardware.
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>

namespace risas_ros {

// The device cannot be opened, is gone, or refuses a setting; the message
// says which device and what happened.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StreamMode {
  int width = 640;
  int height = 480;
  int fps = 30;
};

struct DeviceFrame {
  cv::Mat image;               // colour: CV_8UC3 RGB; depth: CV_16UC1 millimetres, 0 = none
  uint64_t timestamp_us = 0;   // device clock
};

class RgbdDevice {
 public:
  virtual ~RgbdDevice() = default;
  virtual std::string description() const = 0;  // name and URI, for messages
  virtual bool supportsRegistration() const = 0;
  // Depth-to-colour registration: depth then lies on the colour pixel grid.
  virtual void setRegistration(bool enabled) = 0;
  virtual void setFrameSync(bool enabled) = 0;
  virtual void start(const StreamMode& mode) = 0;  // DeviceError when the mode is not offered
  virtual void stop() = 0;
  // The next colour and depth frame of one instant; false when none came
  // within timeout_s; DeviceError when the device is gone.
  virtual bool read(DeviceFrame& color, DeviceFrame& depth, double timeout_s) = 0;
  // Fields of view of the colour camera, radians.
  virtual double horizontalFov() const = 0;
  virtual double verticalFov() const = 0;
};

}  // namespace risas_ros

// RgbdDevice on libopenni2 (Debian's libopenni2-dev: PS1080 driver for
// Kinect/Xtion/PrimeSense, OniFile for .oni recordings).
#pragma once

#include "risas/ros/rgbd_device.hpp"

#include <memory>
#include <string>
#include <vector>

namespace risas_ros {

// "name (vendor) at URI" for every device OpenNI2 can see now.
std::vector<std::string> listOpenNI2Devices();

// device_id: empty for the first device found; a path ending in .oni for a
// recording; "#N" for the N-th device (1-based); else a device URI or a part
// of one (e.g. the USB bus/address). DeviceError, listing what OpenNI2 found,
// when nothing matches.
std::unique_ptr<RgbdDevice> openOpenNI2Device(const std::string& device_id);

// N of a device_id "#N": 1 or more, all digits, or DeviceError naming it
// ("#2x", "#0", "#99999999999" are not N-th devices).
int deviceNumberOf(const std::string& device_id);

}  // namespace risas_ros

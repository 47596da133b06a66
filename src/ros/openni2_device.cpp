#include "risas/ros/openni2_device.hpp"

#include <OpenNI.h>

#include <atomic>
#include <cctype>
#include <charconv>
#include <chrono>
#include <mutex>
#include <sstream>
#include <system_error>

namespace risas_ros {
namespace {

std::string lastError() { return openni::OpenNI::getExtendedError(); }

void initialiseOpenNI() {
  static std::once_flag once;
  static openni::Status status = openni::STATUS_OK;
  std::call_once(once, [] { status = openni::OpenNI::initialize(); });
  if (status != openni::STATUS_OK) throw DeviceError("OpenNI2 failed to initialise: " + lastError());
}

std::vector<openni::DeviceInfo> enumerate() {
  initialiseOpenNI();
  openni::Array<openni::DeviceInfo> list;
  openni::OpenNI::enumerateDevices(&list);
  std::vector<openni::DeviceInfo> devices;
  for (int i = 0; i < list.getSize(); ++i) devices.push_back(list[i]);
  return devices;
}

std::string describe(const openni::DeviceInfo& info) {
  return std::string(info.getName()) + " (" + info.getVendor() + ") at " + info.getUri();
}

class OpenNI2Device final : public RgbdDevice, public openni::OpenNI::DeviceDisconnectedListener {
 public:
  explicit OpenNI2Device(const std::string& uri) : uri_(uri) {
    if (device_.open(uri.c_str()) != openni::STATUS_OK) throw DeviceError("cannot open " + uri + ": " + lastError());
    if (color_.create(device_, openni::SENSOR_COLOR) != openni::STATUS_OK ||
        depth_.create(device_, openni::SENSOR_DEPTH) != openni::STATUS_OK) {
      throw DeviceError(uri + " lacks a colour or a depth sensor: " + lastError());
    }
    openni::OpenNI::addDeviceDisconnectedListener(this);
  }
  ~OpenNI2Device() override {
    openni::OpenNI::removeDeviceDisconnectedListener(this);
    stop();
    color_.destroy();
    depth_.destroy();
    device_.close();
  }

  std::string description() const override { return uri_; }

  bool supportsRegistration() const override {
    return const_cast<openni::Device&>(device_).isImageRegistrationModeSupported(
        openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR);
  }
  void setRegistration(bool enabled) override {
    const auto mode = enabled ? openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR : openni::IMAGE_REGISTRATION_OFF;
    if (device_.setImageRegistrationMode(mode) != openni::STATUS_OK) {
      throw DeviceError(uri_ + " refused the registration mode: " + lastError());
    }
  }
  void setFrameSync(bool enabled) override {
    if (device_.setDepthColorSyncEnabled(enabled) != openni::STATUS_OK) {
      throw DeviceError(uri_ + " refused depth/colour frame sync: " + lastError());
    }
  }

  void start(const StreamMode& mode) override {
    setMode(color_, mode, openni::PIXEL_FORMAT_RGB888, "colour");
    setMode(depth_, mode, openni::PIXEL_FORMAT_DEPTH_1_MM, "depth");
    if (color_.start() != openni::STATUS_OK || depth_.start() != openni::STATUS_OK) {
      throw DeviceError(uri_ + " did not start streaming: " + lastError());
    }
    half_period_us_ = 500000 / std::max(1, mode.fps);
  }
  void stop() override {
    color_.stop();
    depth_.stop();
  }

  bool read(DeviceFrame& color, DeviceFrame& depth, double timeout_s) override {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    openni::VideoStream* streams[] = {&color_, &depth_};
    while (true) {
      if (disconnected_) throw DeviceError(uri_ + " was disconnected");
      const int left_ms = static_cast<int>(
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count());
      if (left_ms <= 0) return false;
      int ready = -1;
      const openni::Status status = openni::OpenNI::waitForAnyStream(streams, 2, &ready, left_ms);
      if (status == openni::STATUS_TIME_OUT) return false;
      if (status != openni::STATUS_OK) throw DeviceError(uri_ + " stopped delivering frames: " + lastError());
      openni::VideoFrameRef frame;
      if (streams[ready]->readFrame(&frame) != openni::STATUS_OK) {
        throw DeviceError(uri_ + " frame could not be read: " + lastError());
      }
      (ready == 0 ? latest_color_ : latest_depth_) = copy(frame, ready == 0 ? CV_8UC3 : CV_16UC1);
      // A pair: both frames taken within half a frame period of each other.
      if (!latest_color_.image.empty() && !latest_depth_.image.empty()) {
        const int64_t gap = static_cast<int64_t>(latest_color_.timestamp_us) - static_cast<int64_t>(latest_depth_.timestamp_us);
        if (std::llabs(gap) <= half_period_us_) {
          color = latest_color_;
          depth = latest_depth_;
          latest_color_ = DeviceFrame();
          latest_depth_ = DeviceFrame();
          return true;
        }
      }
    }
  }

  double horizontalFov() const override { return const_cast<openni::VideoStream&>(color_).getHorizontalFieldOfView(); }
  double verticalFov() const override { return const_cast<openni::VideoStream&>(color_).getVerticalFieldOfView(); }

  void onDeviceDisconnected(const openni::DeviceInfo* info) override {
    if (info && uri_ == info->getUri()) disconnected_ = true;
  }

 private:
  void setMode(openni::VideoStream& stream, const StreamMode& wanted, openni::PixelFormat format, const char* what) {
    const openni::Array<openni::VideoMode>& modes = stream.getSensorInfo().getSupportedVideoModes();
    std::ostringstream offered;
    for (int i = 0; i < modes.getSize(); ++i) {
      const openni::VideoMode& m = modes[i];
      if (m.getPixelFormat() != format) continue;
      offered << " " << m.getResolutionX() << "x" << m.getResolutionY() << "@" << m.getFps();
      if (m.getResolutionX() == wanted.width && m.getResolutionY() == wanted.height && m.getFps() == wanted.fps) {
        if (stream.setVideoMode(m) != openni::STATUS_OK) throw DeviceError(uri_ + " refused its own " + what + " mode");
        return;
      }
    }
    throw DeviceError(uri_ + " offers no " + what + " mode " + std::to_string(wanted.width) + "x" +
                      std::to_string(wanted.height) + "@" + std::to_string(wanted.fps) + "; it offers:" + offered.str());
  }

  static DeviceFrame copy(const openni::VideoFrameRef& frame, int type) {
    const cv::Mat view(frame.getHeight(), frame.getWidth(), type, const_cast<void*>(frame.getData()),
                       static_cast<size_t>(frame.getStrideInBytes()));
    return {view.clone(), frame.getTimestamp()};
  }

  std::string uri_;
  openni::Device device_;
  openni::VideoStream color_, depth_;
  DeviceFrame latest_color_, latest_depth_;
  int64_t half_period_us_ = 16667;
  std::atomic<bool> disconnected_{false};
};

}  // namespace

std::vector<std::string> listOpenNI2Devices() {
  std::vector<std::string> names;
  for (const openni::DeviceInfo& info : enumerate()) names.push_back(describe(info));
  return names;
}

int deviceNumberOf(const std::string& device_id) {
  const auto refused = [&] {
    return DeviceError("device_id " + device_id + " is not #N, the N-th device found (N = 1, 2, ...)");
  };
  if (device_id.size() < 2 || device_id[0] != '#' || !std::isdigit(static_cast<unsigned char>(device_id[1]))) {
    throw refused();
  }
  int n = 0;
  const char* last = device_id.data() + device_id.size();
  const auto [end, error] = std::from_chars(device_id.data() + 1, last, n);
  if (error != std::errc() || end != last || n < 1) throw refused();
  return n;
}

std::unique_ptr<RgbdDevice> openOpenNI2Device(const std::string& device_id) {
  const std::vector<openni::DeviceInfo> devices = enumerate();
  const auto found = [&]() {
    if (devices.empty()) return std::string("no device");
    std::string list;
    for (const openni::DeviceInfo& d : devices) list += "\n  " + describe(d);
    return std::to_string(devices.size()) + " device(s):" + list;
  };
  const bool recording = device_id.size() > 4 && device_id.compare(device_id.size() - 4, 4, ".oni") == 0;
  if (recording) return std::make_unique<OpenNI2Device>(device_id);
  if (devices.empty()) {
    throw DeviceError("no OpenNI2 device found: plug in a Kinect or Xtion (and check its USB power and "
                      "permissions), or set ~device_id to an .oni recording");
  }
  if (device_id.empty()) return std::make_unique<OpenNI2Device>(devices.front().getUri());
  if (device_id[0] == '#') {
    const int n = deviceNumberOf(device_id);
    if (n > static_cast<int>(devices.size())) {
      throw DeviceError("device_id " + device_id + " is out of range; OpenNI2 found " + found());
    }
    return std::make_unique<OpenNI2Device>(devices[static_cast<size_t>(n - 1)].getUri());
  }
  for (const openni::DeviceInfo& d : devices) {
    if (std::string(d.getUri()).find(device_id) != std::string::npos) return std::make_unique<OpenNI2Device>(d.getUri());
  }
  throw DeviceError("no OpenNI2 device matches device_id '" + device_id + "'; OpenNI2 found " + found());
}

}  // namespace risas_ros

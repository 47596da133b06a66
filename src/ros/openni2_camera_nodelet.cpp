// risas/OpenNI2CameraNodelet: a Kinect/Xtion (or an .oni recording) through
// libopenni2, for Debian, which has no openni2_camera. Publishes the
// device's unrectified images, as openni2_camera does (openni2.launch
// rectifies them with image_proc):
//   rgb/image_raw               rgb8
//   rgb/camera_info             from ~camera_info_url if it holds a calibration,
//                               else from the device's fields of view
//   depth_registered/image_raw  16UC1 millimetres, registered to rgb
//   depth_registered/camera_info  the colour camera's, which registered depth has
//                               (depth/image_raw alone when the device cannot register)
// Streams run only while someone subscribes (~always_on to override).
// Parameters: ~device_id ("" first device, "#N", URI part, or file.oni),
// ~width, ~height, ~fps (640, 480, 30), ~depth_registration (true),
// ~frame_sync (true), ~rgb_frame_id, ~depth_frame_id, ~camera_info_url,
// ~reconnect (true: reopen a device that went away; false: shut down).
// No device at start: a message saying so and listing what OpenNI2 found,
// then the node shuts down.
#include "risas/ros/node_params.hpp"
#include "risas/ros/openni2_device.hpp"
#include "risas/ros/rgbd_camera_driver.hpp"

#include <camera_info_manager/camera_info_manager.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <atomic>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace risas_ros {

class OpenNI2CameraNodelet : public nodelet::Nodelet {
 public:
  ~OpenNI2CameraNodelet() override {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::string url;
    try {
      NodeParams params(pnh);
      device_id_ = params.text("device_id", "");
      settings_.mode = {params.whole("width", 640, 1, 10000), params.whole("height", 480, 1, 10000),
                        params.whole("fps", 30, 1, 1000)};
      settings_.depth_registration = params.flag("depth_registration", true);
      settings_.frame_sync = params.flag("frame_sync", true);
      settings_.rgb_frame_id = params.frameId("rgb_frame_id", settings_.rgb_frame_id);
      settings_.depth_frame_id = params.frameId("depth_frame_id", settings_.depth_frame_id);
      always_on_ = params.flag("always_on", false);
      reconnect_ = params.flag("reconnect", true);
      url = params.text("camera_info_url", "");
      params.refuseUnread();
    } catch (const std::invalid_argument& e) {
      NODELET_FATAL("invalid camera parameter: %s", e.what());
      throw;
    }

    const std::string problem = openDevice();
    if (!problem.empty()) {
      NODELET_FATAL("%s", problem.c_str());
      ros::requestShutdown();
      return;
    }
    camera_info_ = driver_->cameraInfoFromFov();
    if (!url.empty()) {
      camera_info_manager::CameraInfoManager manager(ros::NodeHandle(nh, "rgb"), "rgb", url);
      if (manager.isCalibrated()) {
        const sensor_msgs::CameraInfo calibration = manager.getCameraInfo();
        if (const auto info = driver_->cameraInfoFromCalibration(calibration)) {
          camera_info_ = *info;
        } else {
          NODELET_WARN("%s is a calibration for %ux%u, which the %dx%d mode is not a whole division of: using "
                       "intrinsics from the field of view",
                       url.c_str(), calibration.width, calibration.height, settings_.mode.width,
                       settings_.mode.height);
        }
      } else {
        NODELET_WARN("%s holds no calibration: using intrinsics from the field of view", url.c_str());
      }
    }

    {
      std::lock_guard<std::mutex> lock(mutex_);
      image_transport::ImageTransport it(nh);
      const auto connect = [this](const auto&) { connectCb(); };
      pub_color_ = it.advertise("rgb/image_raw", 5, connect, connect);
      pub_depth_ = it.advertise(driver_->depthTopic(), 5, connect, connect);
      pub_info_ = nh.advertise<sensor_msgs::CameraInfo>("rgb/camera_info", 5, connect, connect);
      if (driver_->registered()) {
        pub_depth_info_ = nh.advertise<sensor_msgs::CameraInfo>("depth_registered/camera_info", 5, connect, connect);
      }
    }
    connectCb();
    thread_ = std::thread([this] { publishLoop(); });
  }

  // Opens the device and configures it; what went wrong, or "".
  std::string openDevice() {
    try {
      auto driver = std::make_unique<RgbdCameraDriver>(openOpenNI2Device(device_id_), settings_, [] { return ros::Time::now(); });
      if (!driver->warning().empty()) NODELET_WARN("%s", driver->warning().c_str());
      NODELET_INFO("opened %s: %dx%d@%d, depth %s", driver->device().description().c_str(), settings_.mode.width,
                   settings_.mode.height, settings_.mode.fps, driver->registered() ? "registered to colour" : "unregistered");
      std::lock_guard<std::mutex> lock(mutex_);
      driver_ = std::move(driver);
      return "";
    } catch (const DeviceError& e) {
      return e.what();
    }
  }

  bool wanted() const {
    return always_on_ || pub_color_.getNumSubscribers() > 0 || pub_depth_.getNumSubscribers() > 0 ||
           pub_info_.getNumSubscribers() > 0 || pub_depth_info_.getNumSubscribers() > 0;
  }

  void connectCb() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!driver_) return;
    try {
      if (wanted() && !driver_->streaming()) {
        driver_->start();
        NODELET_INFO("streaming started");
      } else if (!wanted() && driver_->streaming()) {
        driver_->stop();
        NODELET_INFO("nobody subscribes: streaming stopped");
      }
    } catch (const DeviceError& e) {
      NODELET_ERROR("%s", e.what());
    }
  }

  void publishLoop() {
    while (running_ && ros::ok()) {
      std::optional<CameraMessages> messages;
      try {
        std::unique_lock<std::mutex> lock(mutex_);
        if (!driver_ || !driver_->streaming()) {
          lock.unlock();
          std::this_thread::sleep_for(std::chrono::milliseconds(50));
          continue;
        }
        messages = driver_->next(0.5);
      } catch (const DeviceError& e) {
        NODELET_ERROR("%s", e.what());
        if (!recover()) return;
        continue;
      }
      if (!messages) {
        NODELET_WARN_THROTTLE(5.0, "no frames from the device for 0.5 s");
        continue;
      }
      auto info = boost::make_shared<sensor_msgs::CameraInfo>(camera_info_);
      info->header = messages->color->header;
      pub_color_.publish(messages->color);
      pub_depth_.publish(messages->depth);
      pub_info_.publish(info);
      if (pub_depth_info_) {
        auto depth_info = boost::make_shared<sensor_msgs::CameraInfo>(*info);
        depth_info->header = messages->depth->header;
        pub_depth_info_.publish(depth_info);
      }
    }
  }

  // After the device went away: reopen it (~reconnect) or shut down.
  bool recover() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      driver_.reset();
    }
    if (!reconnect_) {
      NODELET_FATAL("device lost and ~reconnect is false: shutting down");
      ros::requestShutdown();
      return false;
    }
    while (running_ && ros::ok()) {
      std::this_thread::sleep_for(std::chrono::seconds(2));
      const std::string problem = openDevice();
      if (problem.empty()) {
        connectCb();
        return true;
      }
      NODELET_WARN_THROTTLE(10.0, "cannot reopen the device yet: %s", problem.c_str());
    }
    return false;
  }

  std::string device_id_;
  CameraSettings settings_;
  bool always_on_ = false, reconnect_ = true;
  sensor_msgs::CameraInfo camera_info_;

  std::mutex mutex_;  // guards driver_ between the publishing thread and connect callbacks
  std::unique_ptr<RgbdCameraDriver> driver_;
  image_transport::Publisher pub_color_, pub_depth_;
  ros::Publisher pub_info_, pub_depth_info_;  // depth_info_ only when registered
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace risas_ros

PLUGINLIB_EXPORT_CLASS(risas_ros::OpenNI2CameraNodelet, nodelet::Nodelet)

// What the bag writers (risas_dataset_to_bag, risas_tum_to_bag) share: their
// --frame-id, a bag written with one-line errors, and one registered RGB-D
// frame written as an OpenNI camera's three topics.
#pragma once

#include "../tools/cli.hpp"
#include "risas/errors.hpp"
#include "risas/rgbd_frame.hpp"
#include "risas/ros/conversions.hpp"
#include "risas/ros/node_params.hpp"

#include <cv_bridge/cv_bridge.h>
#include <rosbag/bag.h>
#include <sensor_msgs/image_encodings.h>

#include <memory>
#include <string>

namespace risas_ros {

// The tools' --frame-id (the images' and camera_info's frame): a tf frame id
// as the nodes' frame parameters take it, else wrong usage.
inline std::string frameIdOption(const risas::cli::Args& args) {
  const std::string id = args.get("frame-id", "camera_rgb_optical_frame");
  if (!isTfFrameId(id)) {
    throw risas::cli::UsageError(std::string("--frame-id must be ") + kTfFrameIdRule + " (got '" + id + "')");
  }
  return id;
}

// A bag open for writing whose failures (a full disk, a lost mount) are
// InputErrors naming it. rosbag::Bag's destructor closes the bag, writing
// its index, and lets that write's exception out of the destructor: a
// failed write unwound into it and ended the tool in std::terminate. After
// a failure the Bag is abandoned, not destroyed, since its destructor would
// retry the close; the tools end with the error right after.
class BagWriter {
 public:
  explicit BagWriter(const std::string& path) : path_(path), bag_(std::make_unique<rosbag::Bag>()) {
    guarded([&] { bag_->open(path, rosbag::bagmode::Write); });
  }
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;
  ~BagWriter() {
    try {
      if (bag_) bag_->close();
    } catch (const rosbag::BagException&) {
      abandon();
    }
  }

  template <class M>
  void write(const std::string& topic, const ros::Time& stamp, const M& message) {
    guarded([&] { bag_->write(topic, stamp, message); });
  }
  // Writes the index: the bag is complete once this returns.
  void close() {
    guarded([&] { bag_->close(); });
  }

 private:
  template <class F>
  void guarded(F&& call) {
    if (!bag_) throw risas::InputError("bag " + path_ + " was abandoned after a failed write");
    try {
      call();
    } catch (const rosbag::BagException& e) {
      abandon();
      throw risas::InputError("cannot write bag " + path_ + ": " + e.what());
    }
  }
  void abandon() { static_cast<void>(bag_.release()); }  // deliberately not deleted: see the class comment

  std::string path_;
  std::unique_ptr<rosbag::Bag> bag_;
};

// <ns>/rgb/image_rect_color (bgr8), <ns>/depth_registered/image_raw (16UC1
// millimetres or 32FC1 metres, as `depth` is) and <ns>/rgb/camera_info, all
// stamped header.stamp. The frame is validated first (sizes, intrinsics,
// depth present).
inline void writeRgbdFrame(BagWriter& bag, const std::string& ns, const std_msgs::Header& header, const cv::Mat& bgr,
                           const cv::Mat& depth, const risas::Intrinsics& K) {
  const risas::RgbdFrame check(bgr, depth, K);
  sensor_msgs::CameraInfo info = cameraInfoFromIntrinsics(K, check.size());
  info.header = header;
  const std::string depth_encoding =
      depth.type() == CV_16UC1 ? sensor_msgs::image_encodings::TYPE_16UC1 : sensor_msgs::image_encodings::TYPE_32FC1;
  bag.write(ns + "/rgb/image_rect_color", header.stamp,
            cv_bridge::CvImage(header, sensor_msgs::image_encodings::BGR8, bgr).toImageMsg());
  bag.write(ns + "/depth_registered/image_raw", header.stamp, cv_bridge::CvImage(header, depth_encoding, depth).toImageMsg());
  bag.write(ns + "/rgb/camera_info", header.stamp, info);
}

}  // namespace risas_ros

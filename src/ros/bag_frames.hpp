// What the bag writers (risas_dataset_to_bag, risas_tum_to_bag) share: a
// bag opened for writing with a one-line error, and one registered RGB-D
// frame written as an OpenNI camera's three topics.
#pragma once

#include "risas/errors.hpp"
#include "risas/rgbd_frame.hpp"
#include "risas/ros/conversions.hpp"

#include <cv_bridge/cv_bridge.h>
#include <rosbag/bag.h>
#include <sensor_msgs/image_encodings.h>

#include <string>

namespace risas_ros {

inline void openBagForWriting(rosbag::Bag& bag, const std::string& path) {
  try {
    bag.open(path, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw risas::InputError("cannot write bag " + path + ": " + e.what());
  }
}

// <ns>/rgb/image_rect_color (bgr8), <ns>/depth_registered/image_raw (16UC1
// millimetres or 32FC1 metres, as `depth` is) and <ns>/rgb/camera_info, all
// stamped header.stamp. The frame is validated first (sizes, intrinsics,
// depth present).
inline void writeRgbdFrame(rosbag::Bag& bag, const std::string& ns, const std_msgs::Header& header, const cv::Mat& bgr,
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

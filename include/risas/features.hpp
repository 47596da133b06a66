// The features of one frame, as the tools and files carry them.
#pragma once

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace risas {

// What RISAS knows of a described keypoint in 3D.
struct KeypointGeometry {
  cv::Point3f point;     // metres, camera optical frame
  cv::Vec3f normal;      // unit, facing the camera
  float support_radius;  // radius of the described patch on the surface, metres
};

struct Features {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;                    // N x D CV_32F
  std::vector<KeypointGeometry> geometry; // N, or empty when unknown
  // DescriptorParams::layout() of the descriptors; empty when unknown (ORB's,
  // files written before the layout was recorded). Descriptors of different
  // layouts must not be matched, even when their widths agree.
  std::string descriptor_layout;

  std::vector<cv::Point3f> points() const {
    std::vector<cv::Point3f> p;
    p.reserve(geometry.size());
    for (const KeypointGeometry& g : geometry) p.push_back(g.point);
    return p;
  }
};

// Whether descriptors of these two layouts (Features::descriptor_layout) may
// be matched: the same layout, or either unknown.
inline bool layoutsAgree(const std::string& a, const std::string& b) { return a.empty() || b.empty() || a == b; }

}  // namespace risas

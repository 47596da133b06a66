// What the fuzz drivers share (fuzz_core.cpp, and fuzz_ros_messages.cpp in
// a catkin build): typed values read off an input, the invariant check that
// aborts, random images and parameters, and the check of extracted features.
#pragma once

#include "risas/errors.hpp"
#include "risas/features.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <vector>

namespace risas_fuzz {

// Reads typed values off the input, zeros once it runs out.
class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  int in(int lo, int hi) { return lo + static_cast<int>(word() % static_cast<uint32_t>(hi - lo + 1)); }
  uint32_t word() {
    uint32_t w = 0;
    for (int i = 0; i < 4; ++i) w = w << 8 | byte();
    return w;
  }
  // Mostly ordinary values, now and then the extremes that broke things.
  double number(double lo, double hi) {
    switch (byte() % 64) {
      case 0: return std::numeric_limits<double>::quiet_NaN();
      case 1: return std::numeric_limits<double>::infinity();
      case 2: return -1.0;
      case 3: return 0.0;
      case 4: return 1e300;
      case 5: return 1e-300;
      default: return lo + (hi - lo) * (word() / 4294967295.0);
    }
  }
  size_t left() const { return size_ - pos_; }
  std::string rest() { return std::string(reinterpret_cast<const char*>(data_ + pos_), left()); }

 private:
  const uint8_t* data_;
  size_t size_, pos_ = 0;
};

[[noreturn]] inline void breach(const char* what) {
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
  std::abort();
}
inline void require(bool ok, const char* what) {
  if (!ok) breach(what);
}

// One input's case, run so that whatever escapes it aborts: an InputError
// (each step catches its own) or any other exception (none is documented;
// XmlRpc's derive from no std type).
template <class Case>
void runCase(Case&& run) {
  try {
    run();
  } catch (const risas::InputError&) {
    breach("an InputError escaped a step that should have caught it");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "undocumented exception: %s\n", e.what());
    std::abort();
  } catch (...) {
    breach("an exception of no std type escaped");
  }
}

// An image of `type`: raw bytes, a pattern, or (for depth types) a scene:
// a tilted plane with a box standing out of it, holes where the input says.
inline cv::Mat image(Bytes& in, cv::Size size, int type) {
  cv::Mat m(size, type);
  const int style = in.byte() % 4;
  if (style == 3 && (type == CV_16UC1 || type == CV_32FC1)) {
    const float base = 0.4f + in.byte() * 0.01f;
    const float du = (in.byte() - 128) * 1e-4f;
    const float dv = (in.byte() - 128) * 1e-4f;
    cv::Rect box;
    box.x = in.in(0, size.width), box.y = in.in(0, size.height), box.width = in.in(2, 30), box.height = in.in(2, 30);
    const int holes = in.byte();
    for (int r = 0; r < m.rows; ++r) {
      for (int c = 0; c < m.cols; ++c) {
        float z = base + du * c + dv * r - (box.contains({c, r}) ? 0.15f : 0.0f);
        if (holes && (r * 31 + c * 17) % 256 < holes / 8) z = 0.0f;
        if (type == CV_16UC1) m.at<uint16_t>(r, c) = static_cast<uint16_t>(std::clamp(z * 1000.0f, 0.0f, 65535.0f));
        else m.at<float>(r, c) = z > 0.0f ? z : NAN;
      }
    }
    return m;
  }
  uint8_t* p = m.data;
  const size_t total = m.total() * m.elemSize();
  for (size_t i = 0; i < total; ++i) p[i] = style == 0 ? in.byte() : static_cast<uint8_t>((i % 13) * 19 * style + i / 97);
  if (type == CV_32FC1 && style != 0) {  // plausible metres, with NaN and inf holes
    for (int r = 0; r < m.rows; ++r) {
      for (int c = 0; c < m.cols; ++c) {
        const uint8_t b = in.byte();
        m.at<float>(r, c) = b == 0 ? NAN : b == 1 ? INFINITY : 0.3f + b * 0.01f;
      }
    }
  }
  return m;
}

inline risas::RisasParams params(Bytes& in) {
  risas::RisasParams p;
  if (in.byte() % 2) return p;
  p.detector.tau = in.number(0.0, 1.0);
  p.detector.max_keypoints = in.in(1, 300);
  p.detector.min_keypoints = in.in(0, 300);
  p.detector.border = in.in(0, 12);
  p.descriptor.n_pie = in.in(1, 16);
  p.descriptor.n_bin = in.in(1, 16);
  p.descriptor.n_vec = in.in(0, 8);
  p.descriptor.n_ring = in.in(1, 3);
  p.descriptor.shape_weight = p.descriptor.n_vec > 0 && in.byte() % 2 ? in.number(0.01, 2.0) : 0.0;
  p.descriptor.rho_threshold = in.number(0.0, 1.0);
  p.descriptor.support_radius = in.number(0.0, 0.2);
  p.descriptor.shape_orientation = in.byte() % 2;
  p.descriptor.gradient_orientation = in.byte() % 2;
  p.descriptor.soft_binning = in.byte() % 2;
  p.descriptor.sample_blur = in.number(0.0, 4.0);
  p.descriptor.grey_noise = in.byte() % 2 ? -1.0 : in.number(0.0, 64.0);
  p.geometry.normal_stride = in.in(1, 4);
  p.geometry.normal_radius = in.in(1, 8);
  return p;
}

inline void checkFeatures(const risas::RgbdFrame& frame, const std::vector<cv::KeyPoint>& keypoints,
                   const cv::Mat& descriptors, const std::vector<risas::KeypointGeometry>& geometry, int dimension) {
  require(descriptors.rows == static_cast<int>(keypoints.size()), "one descriptor row per keypoint");
  require(keypoints.empty() || (descriptors.cols == dimension && descriptors.type() == CV_32F), "descriptor shape");
  require(geometry.size() == keypoints.size(), "one geometry per keypoint");
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const cv::Point2f p = keypoints[i].pt;
    require(p.x >= 0 && p.y >= 0 && p.x <= frame.size().width - 1 && p.y <= frame.size().height - 1,
            "keypoint inside the image");
    double norm = 0.0;
    for (int d = 0; d < descriptors.cols; ++d) {
      const float v = descriptors.at<float>(static_cast<int>(i), d);
      require(std::isfinite(v) && v >= 0.0f, "finite, non-negative descriptor");
      norm += static_cast<double>(v) * v;
    }
    require(std::abs(norm - 1.0) < 1e-4, "unit-length descriptor");
    const risas::KeypointGeometry& g = geometry[i];
    require(std::isfinite(g.point.x) && std::isfinite(g.point.y) && g.point.z > 0.0f, "finite point in front");
    require(std::abs(cv::norm(g.normal) - 1.0) < 1e-3, "unit normal");
  }
}

}  // namespace risas_fuzz

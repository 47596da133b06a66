// Fuzz driver for the ROS layer's checks of what arrives on its topics and
// parameters (risas/ros/conversions.hpp), as a bag or a misconfigured node
// can deliver it: colour, depth and camera_info messages (frameFromMessages:
// encodings right and wrong, sizes that differ, steps short, long and odd,
// buffers short, big-endian data, frame_ids, K and P with NaN, infinities
// and zeros, binning and roi of any value), camera_info alone
// (intrinsicsFromCameraInfo), the two stamps of a pair (checkOneMoment: any
// seconds and nanoseconds), a KeypointArray of any shape and values
// (fromMessage) tracked by the odometry as its nodelet does, and parameter
// sections of any names, types and values (paramsFromXmlRpc).
//
// Invariants it holds the layer to (a breach aborts, and so does any
// sanitizer report):
//   - the only exception is risas::InputError (std::invalid_argument, the
//     parameter reader's, for parameters);
//   - a frame taken has the message's size, its depth in metres is the
//     message's pixel as written (step, byte order and unit applied), a
//     mono8 image's grey is its pixels, and its intrinsics are finite and
//     positive; its features, published and read back (toMessage,
//     fromMessage), are the same keypoints and descriptors, and its cloud
//     (toPointCloud) holds one finite point per keypoint;
//   - an array read from a message has finite pixels and descriptors, and
//     an odometry fed such arrays has a finite pose;
//   - parameters taken pass validate().
//
// Built in a catkin workspace as `risas_ros_fuzz_loop` (with
// fuzz_loop_main.cpp); test/ros/test_ros_fuzz.cpp runs it as a test.
#include "fuzz_support.hpp"
#include "risas/errors.hpp"
#include "risas/odometry.hpp"
#include "risas/params_fields.hpp"
#include "risas/risas.hpp"
#include "risas/ros/conversions.hpp"

#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace risas_fuzz;
namespace enc = sensor_msgs::image_encodings;

// Mostly a name from `names`, now and then anything.
std::string pick(Bytes& in, const std::vector<std::string>& names) {
  if (in.byte() % 16 == 0) {
    std::string any;
    for (int n = in.in(0, 12); n > 0; --n) any += static_cast<char>(in.byte());
    return any;
  }
  return names[in.byte() % names.size()];
}

// An image message of `encoding` and size holding fuzz_support's image (a
// scene for depth), its step and buffer as a publisher fills them; when
// `wrong`, now and then not: a step short or long (by any bytes, so not a
// whole pixel), a buffer short or long.
sensor_msgs::Image imageMessage(Bytes& in, const std::string& encoding, cv::Size size, const std::string& frame,
                                bool wrong) {
  sensor_msgs::Image m;
  m.header.frame_id = frame;
  m.encoding = encoding;
  m.width = static_cast<uint32_t>(size.width);
  m.height = static_cast<uint32_t>(size.height);
  m.is_bigendian = in.byte() % 8 == 0;
  const bool known = enc::isColor(encoding) || enc::isMono(encoding) || encoding == enc::TYPE_16UC1 ||
                     encoding == enc::TYPE_32FC1;
  const int channels = known ? enc::numChannels(encoding) : 1, depth = known ? enc::bitDepth(encoding) / 8 : 1;
  const uint32_t row = m.width * static_cast<uint32_t>(channels * depth);
  m.step = row;
  switch (wrong ? in.byte() % 4 : 4) {
    case 0: m.step = row + static_cast<uint32_t>(in.in(1, 9)); break;  // padded, maybe by part of a pixel
    case 1: m.step = row > 0 ? row - 1 : 0; break;                      // a row cut short
    case 2: m.step = in.word(); break;
    default: break;
  }
  size_t bytes = static_cast<size_t>(std::min<uint64_t>(static_cast<uint64_t>(m.step) * m.height, 1u << 20));
  switch (wrong ? in.byte() % 4 : 4) {
    case 0: bytes = bytes > 0 ? bytes - static_cast<size_t>(in.in(1, 4)) % (bytes + 1) : 0; break;
    case 1: bytes += static_cast<size_t>(in.in(1, 16)); break;
    default: break;
  }
  m.data.resize(bytes);
  const int type = encoding == enc::TYPE_32FC1 ? CV_32FC1 : CV_MAKETYPE(depth == 2 ? CV_16U : CV_8U, channels);
  const cv::Mat pixels = image(in, size, type);
  for (int r = 0; r < pixels.rows; ++r) {  // as far as the step and the buffer hold them
    const size_t at = static_cast<size_t>(r) * m.step;
    const size_t n = std::min<size_t>({pixels.cols * pixels.elemSize(), m.step, at < bytes ? bytes - at : 0});
    for (size_t b = 0; b < n; ++b) {
      const size_t e = m.is_bigendian ? b / depth * depth + (depth - 1 - b % depth) : b;  // byte order
      m.data[at + b] = pixels.ptr(r)[e];
    }
  }
  return m;
}

// The colour camera's camera_info for `size`; when `wrong`, now and then
// with other K, P, binning, roi or size.
sensor_msgs::CameraInfo cameraInfo(Bytes& in, cv::Size size, const std::string& frame, bool wrong) {
  risas::Intrinsics K;
  K.fx = in.in(20, 150), K.fy = in.in(20, 150), K.cx = in.in(0, size.width), K.cy = in.in(0, size.height);
  sensor_msgs::CameraInfo info = risas_ros::cameraInfoFromIntrinsics(K, size);
  info.header.frame_id = in.byte() % 8 == 0 ? "" : frame;
  if (!wrong) return info;
  if (in.byte() % 4 == 0) {
    for (double& v : info.P) v = in.byte() % 4 ? v : in.number(-100.0, 200.0);
  }
  if (in.byte() % 8 == 0) info.P.fill(0.0);  // K alone
  if (in.byte() % 8 == 0) {
    for (double& v : info.K) v = in.byte() % 4 ? v : in.number(-100.0, 200.0);
  }
  if (in.byte() % 4 == 0) {
    info.binning_x = static_cast<uint32_t>(in.in(0, 4)), info.binning_y = static_cast<uint32_t>(in.in(0, 4));
    info.width *= std::max(info.binning_x, 1u), info.height *= std::max(info.binning_y, 1u);
  }
  if (in.byte() % 6 == 0) {
    info.roi.x_offset = in.word() % 64, info.roi.y_offset = in.word() % 64;
    info.roi.width = in.byte() % 4 ? static_cast<uint32_t>(size.width) : in.word();
    info.roi.height = in.byte() % 4 ? static_cast<uint32_t>(size.height) : in.word();
    info.roi.do_rectify = in.byte() % 2;
  }
  if (in.byte() % 8 == 0) info.width = in.word() % 100000, info.height = in.word() % 100000;
  return info;
}

// The depth in metres the frame must hold at (r, c), from the message's
// bytes as written.
float depthOf(const sensor_msgs::Image& m, int r, int c) {
  const bool metres = m.encoding == enc::TYPE_32FC1;
  const size_t size = metres ? 4 : 2;
  uint8_t bytes[4];
  const uint8_t* p = &m.data[static_cast<size_t>(r) * m.step + static_cast<size_t>(c) * size];
  for (size_t b = 0; b < size; ++b) bytes[b] = m.is_bigendian ? p[size - 1 - b] : p[b];
  if (metres) {
    float v;
    std::memcpy(&v, bytes, 4);
    return v > 0.0f && v <= risas::RgbdFrame::kMaxDepth ? v : NAN;
  }
  uint16_t v;
  std::memcpy(&v, bytes, 2);
  return v == 0 ? NAN : v * 0.001f;
}

bool sameValue(float a, float b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

// Published and read back: the same keypoints and descriptors; the cloud one
// finite point a keypoint.
void checkPublished(const risas::Features& f, const sensor_msgs::CameraInfo& info) {
  std_msgs::Header header;
  header.frame_id = "camera";
  const risas::KeypointArrayPtr message = risas_ros::toMessage(f, header, info);
  const risas::Features back = risas_ros::fromMessage(*message);
  require(back.keypoints.size() == f.keypoints.size(), "as many keypoints read back");
  for (size_t i = 0; i < f.keypoints.size(); ++i) {
    require(back.keypoints[i].pt == f.keypoints[i].pt && back.geometry[i].point == f.geometry[i].point,
            "the same keypoints read back");
  }
  require(f.keypoints.empty() || cv::norm(back.descriptors, f.descriptors, cv::NORM_INF) == 0.0,
          "the same descriptors read back");
  const sensor_msgs::PointCloud2Ptr cloud = risas_ros::toPointCloud(f, header);
  require(cloud->width == f.geometry.size() && cloud->height == 1, "one cloud point per keypoint");
  require(cloud->data.size() == static_cast<size_t>(cloud->width) * cloud->point_step, "the cloud's buffer");
  for (size_t i = 0; i + 4 <= cloud->data.size(); i += 4) {
    float v;
    std::memcpy(&v, &cloud->data[i], 4);
    require(std::isfinite(v), "finite cloud values");
  }
}

void fuzzImages(Bytes& in) {
  static const std::vector<std::string> colours = {enc::RGB8,  enc::BGR8,        enc::RGBA8, enc::BGRA8,
                                                   enc::MONO8, enc::MONO16,      enc::BGR16, enc::TYPE_16UC1,
                                                   "yuv422",   enc::BAYER_RGGB8, ""};
  static const std::vector<std::string> depths = {enc::TYPE_16UC1, enc::TYPE_32FC1, enc::MONO16, enc::TYPE_16SC1,
                                                  enc::TYPE_64FC1, enc::MONO8,      enc::RGB8,   ""};
  static const std::vector<std::string> frames = {"camera_rgb_optical_frame", "camera_depth_optical_frame", ""};
  // Most cases messages a camera publishes, so that the checks behind the
  // refusals are reached; the rest anything at all.
  const bool wrong = in.byte() % 8 == 0;
  // One value per statement, as in fuzz_core.cpp: a call's arguments are
  // read in the compiler's order, and an input must mean the same to every build.
  cv::Size size;
  size.width = in.in(8, 64), size.height = in.in(8, 48);
  std::string frame = frames[in.byte() % 2];
  std::string colour_encoding = colours[in.byte() % 5], depth_encoding = depths[in.byte() % 2];
  cv::Size depth_size = size;
  if (wrong) {
    size.width = in.in(0, 64), size.height = in.in(0, 48);
    frame = pick(in, frames);
    colour_encoding = pick(in, colours);
    depth_encoding = pick(in, depths);
    depth_size = size;
    if (in.byte() % 4 == 0) depth_size.width = in.in(0, 64), depth_size.height = in.in(0, 48);
  }
  const sensor_msgs::Image colour = imageMessage(in, colour_encoding, size, frame, wrong);
  const std::string depth_frame = wrong && in.byte() % 4 == 0 ? pick(in, frames) : frame;
  const sensor_msgs::Image depth = imageMessage(in, depth_encoding, depth_size, depth_frame, wrong);
  const sensor_msgs::CameraInfo info = cameraInfo(in, size, frame, wrong);

  try {
    const risas::Intrinsics K = risas_ros::intrinsicsFromCameraInfo(info);
    require(std::isfinite(K.fx) && std::isfinite(K.fy) && K.fx > 0 && K.fy > 0, "finite, positive focal lengths");
  } catch (const risas::InputError&) {
  }
  risas::RgbdFrame f;
  try {
    f = risas_ros::frameFromMessages(colour, depth, info);
  } catch (const risas::InputError&) {
    return;
  }
  require(f.size() == cv::Size(static_cast<int>(colour.width), static_cast<int>(colour.height)),
          "a frame of the message's size");
  require(std::isfinite(f.intrinsics().fx) && f.intrinsics().fx > 0 && f.intrinsics().fy > 0, "usable intrinsics");
  for (int probe = 0; probe < 4; ++probe) {
    const int r = in.in(0, f.size().height - 1), c = in.in(0, f.size().width - 1);
    require(sameValue(f.depth().at<float>(r, c), depthOf(depth, r, c)), "the message's depth, in metres");
    if (colour.encoding == enc::MONO8) {
      require(f.gray().at<uint8_t>(r, c) == colour.data[static_cast<size_t>(r) * colour.step + c], "mono8 as grey");
    }
  }
  if (in.byte() % 2) return;  // extraction is the slow part: every other frame
  risas::RisasParams params;
  params.detector.max_keypoints = in.in(1, 60);
  const cv::Ptr<risas::Risas> risas = risas::Risas::create(params);
  const risas::Features features = risas->extract(f);
  checkFeatures(f, features.keypoints, features.descriptors, features.geometry, risas->descriptorSize());
  checkPublished(features, info);
}

// Two stamps of any seconds and nanoseconds (a message's nanoseconds are not
// normalised) and any bound.
void fuzzStamps(Bytes& in) {
  std_msgs::Header colour, depth;
  colour.stamp.sec = in.word(), colour.stamp.nsec = in.byte() % 8 ? in.word() % 1000000000u : in.word();
  depth.stamp = colour.stamp;
  if (in.byte() % 2) depth.stamp.sec = in.byte() % 2 ? colour.stamp.sec + in.in(0, 2) : in.word();
  depth.stamp.nsec = in.byte() % 8 ? in.word() % 1000000000u : in.word();
  const double bound = in.number(0.0, 1.0);
  try {
    const std::string warning = risas_ros::checkOneMoment(colour, depth, bound);
    require(warning.empty() || warning.find("apart") != std::string::npos, "a warning says how far apart");
  } catch (const risas::InputError& e) {
    require(std::string(e.what()).find("apart") != std::string::npos, "an error says how far apart");
  }
}

// A KeypointArray of any shape and values, read as the odometry nodelet
// reads it, and tracked twice.
void fuzzKeypointArrays(Bytes& in) {
  // An array holds hundreds of values and one non-finite pixel or descriptor
  // value refuses it: here only one value in 128 is number()'s extremes, so
  // that most arrays reach the odometry.
  const auto value = [&in](double lo, double hi) {
    return static_cast<float>(in.byte() % 128 ? lo + (hi - lo) * (in.word() / 4294967295.0) : in.number(lo, hi));
  };
  risas::Odometry odometry;
  for (int frame = 0; frame < 2; ++frame) {
    risas::KeypointArray m;
    const int n = in.in(0, 40);
    m.descriptor_dim = in.byte() % 8 ? 8 : in.word();
    m.descriptor_layout = in.byte() % 8 ? "fuzz" : "other";
    m.keypoints.resize(static_cast<size_t>(n));
    for (risas::Keypoint& k : m.keypoints) {
      k.x = value(0.0, 64.0);
      k.y = value(0.0, 48.0);
      k.point.x = static_cast<float>(in.number(-1.0, 1.0));
      k.point.y = static_cast<float>(in.number(-1.0, 1.0));
      k.point.z = static_cast<float>(in.number(0.3, 4.0));
      k.normal = {0.0f, 0.0f, -1.0f};
    }
    size_t values = static_cast<size_t>(n) * (m.descriptor_dim == 8 ? 8 : 0);
    if (in.byte() % 8 == 0) values = in.word() % 512;
    m.descriptors.resize(values);
    for (float& v : m.descriptors) v = value(0.0, 1.0);
    try {
      const risas::Features f = risas_ros::fromMessage(m);
      for (const cv::KeyPoint& k : f.keypoints) {
        require(std::isfinite(k.pt.x) && std::isfinite(k.pt.y), "finite pixels taken");
      }
      require(f.descriptors.empty() || cv::checkRange(f.descriptors), "finite descriptors taken");
      const risas::OdometryResult r = odometry.track(f);
      require(r.world_T_camera.matrix().allFinite(), "a finite pose");
    } catch (const risas::InputError&) {
    }
  }
}

// Parameter sections as the server gives them: RISAS's names mostly, any
// type and value.
void fuzzParameters(Bytes& in) {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> known = [] {
    std::vector<std::pair<std::string, std::vector<std::string>>> sections;
    risas::RisasParams names;
    risas::visitSections(names, [&](const char* section, auto& fields) {
      sections.emplace_back(section, std::vector<std::string>());
      risas::visitFields(fields, [&](const char* name, auto&&...) { sections.back().second.emplace_back(name); });
    });
    return sections;
  }();
  XmlRpc::XmlRpcValue sections;
  for (int s = in.in(0, 3); s > 0; --s) {
    const auto& [section, fields] = known[in.byte() % known.size()];
    const std::string name = in.byte() % 16 ? section : pick(in, {section, "detectr", ""});
    XmlRpc::XmlRpcValue values;
    if (in.byte() % 16 == 0) {
      values = XmlRpc::XmlRpcValue(in.in(0, 5));  // not a struct
    } else {
      for (int f = in.in(0, 4); f > 0; --f) {
        XmlRpc::XmlRpcValue& v = values[pick(in, fields)];
        v.clear();  // a name picked twice: its earlier type would refuse the next
        switch (in.byte() % 6) {
          case 0: v = static_cast<bool>(in.byte() % 2); break;
          case 1: v = in.in(-3, 300); break;
          case 2: v = in.number(0.0, 1.0); break;
          case 3: v = pick(in, {"0", "1", "true", "0.5", "nan", ""}); break;
          case 4: v[0] = 1; break;  // a list
          default: v["a"] = 1; break;  // a map
        }
      }
    }
    sections[name] = values;
  }
  try {
    risas_ros::paramsFromXmlRpc(sections).validate();
  } catch (const std::invalid_argument&) {  // risas::InputError among them
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  runCase([&] {
    switch (in.byte() % 4) {
      case 0: fuzzImages(in); break;
      case 1: fuzzStamps(in); break;
      case 2: fuzzKeypointArrays(in); break;
      default: fuzzParameters(in); break;
    }
  });
  return 0;
}

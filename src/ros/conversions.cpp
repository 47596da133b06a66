#include "risas/ros/conversions.hpp"

#include "risas/errors.hpp"
#include "risas/params_fields.hpp"
#include "risas/twist.hpp"

#include <image_geometry/pinhole_camera_model.h>
#include <opencv2/core/persistence.hpp>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <type_traits>

namespace risas_ros {

using risas::ColorOrder;
using risas::InputError;
using risas::KeypointGeometry;
using risas::Keypoint;
namespace enc = sensor_msgs::image_encodings;

namespace {

// The camera model of the image the CameraInfo comes with: binning and ROI
// applied, as image_geometry applies them (image_proc's crop_decimate and
// drivers' reduced modes publish full-resolution K and P with binning_x/y
// and roi set). A CameraInfo with K alone is read as if P were [K | 0].
image_geometry::PinholeCameraModel cameraModelOf(const sensor_msgs::CameraInfo& info) {
  const auto all_zero = [](const auto& m) { return std::all_of(m.begin(), m.end(), [](double v) { return v == 0.0; }); };
  sensor_msgs::CameraInfo filled = info;
  if (all_zero(info.P)) {
    if (all_zero(info.K)) throw InputError("camera_info has an all-zero K and P: the camera is not calibrated");
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) filled.P[static_cast<size_t>(4 * r + c)] = info.K[static_cast<size_t>(3 * r + c)];
    }
  }
  image_geometry::PinholeCameraModel model;
  try {
    model.fromCameraInfo(filled);
  } catch (const std::exception& e) {
    throw InputError(std::string("camera_info cannot be read as a pinhole camera: ") + e.what());
  }
  return model;
}

Intrinsics intrinsicsOf(const image_geometry::PinholeCameraModel& model) {
  const cv::Matx34d& P = model.projectionMatrix();
  return Intrinsics::fromMatrix(cv::Matx33d(P(0, 0), P(0, 1), P(0, 2), P(1, 0), P(1, 1), P(1, 2), P(2, 0), P(2, 1), P(2, 2)));
}

}  // namespace

Intrinsics intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info) { return intrinsicsOf(cameraModelOf(info)); }

sensor_msgs::CameraInfo cameraInfoFromIntrinsics(const Intrinsics& K, cv::Size size) {
  sensor_msgs::CameraInfo info;
  info.width = static_cast<uint32_t>(size.width);
  info.height = static_cast<uint32_t>(size.height);
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {K.fx, 0.0, K.cx, 0.0, K.fy, K.cy, 0.0, 0.0, 1.0};
  info.R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.P = {K.fx, 0.0, K.cx, 0.0, 0.0, K.fy, K.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  return info;
}

namespace {

// A message whose buffer is shorter than step x height (or whose step is
// shorter than a row) would be read past its end.
void checkBuffer(const sensor_msgs::Image& image, const char* what) {
  const size_t row = static_cast<size_t>(image.width) * enc::numChannels(image.encoding) * (enc::bitDepth(image.encoding) / 8);
  if (image.step < row || image.data.size() < static_cast<size_t>(image.step) * image.height) {
    throw InputError(std::string(what) + " image message is malformed: " + std::to_string(image.data.size()) +
                     " bytes for " + std::to_string(image.height) + " rows of step " + std::to_string(image.step) +
                     " (a row needs " + std::to_string(row) + ")");
  }
}

// The message's pixels as a cv::Mat of `type`, without a copy when they can
// be: a step that is no multiple of the pixel size (legal: step is any row
// length in bytes) and big-endian data are copied row by row, the latter
// with its bytes swapped. The Mat may point into the message.
cv::Mat imageOf(const sensor_msgs::Image& image, int type) {
  const size_t elem = CV_ELEM_SIZE(type), elem1 = CV_ELEM_SIZE1(type);
  const int rows = static_cast<int>(image.height), cols = static_cast<int>(image.width);
  uchar* data = const_cast<uchar*>(image.data.data());
  const bool swap = image.is_bigendian && elem1 > 1;
  if (rows == 0 || cols == 0) return cv::Mat(rows, cols, type);  // no pixels to copy (RgbdFrame refuses it)
  if (image.step % elem == 0 && !swap) return cv::Mat(rows, cols, type, data, image.step);
  cv::Mat copy(rows, cols, type);
  const size_t row_bytes = static_cast<size_t>(cols) * elem;
  for (int r = 0; r < rows; ++r) {
    const uchar* in = data + static_cast<size_t>(r) * image.step;
    uchar* out = copy.ptr(r);
    if (!swap) {
      std::memcpy(out, in, row_bytes);
      continue;
    }
    for (size_t b = 0; b < row_bytes; b += elem1) std::reverse_copy(in + b, in + b + elem1, out + b);
  }
  return copy;
}

int cvTypeOf(const std::string& encoding) {
  if (encoding == enc::MONO8) return CV_8UC1;
  if (encoding == enc::RGB8 || encoding == enc::BGR8) return CV_8UC3;
  if (encoding == enc::RGBA8 || encoding == enc::BGRA8) return CV_8UC4;
  if (encoding == enc::TYPE_16UC1) return CV_16UC1;
  return CV_32FC1;  // TYPE_32FC1: the callers have checked the encodings
}

}  // namespace

RgbdFrame frameFromMessages(const sensor_msgs::Image& color, const sensor_msgs::Image& depth,
                            const sensor_msgs::CameraInfo& info) {
  static const std::vector<std::string> colour_encodings = {enc::RGB8, enc::BGR8, enc::RGBA8, enc::BGRA8, enc::MONO8};
  if (std::find(colour_encodings.begin(), colour_encodings.end(), color.encoding) == colour_encodings.end()) {
    throw InputError("colour image encoding '" + color.encoding + "' is not rgb8, bgr8, rgba8, bgra8 or mono8");
  }
  if (depth.encoding != enc::TYPE_16UC1 && depth.encoding != enc::TYPE_32FC1) {
    throw InputError("depth image encoding '" + depth.encoding + "' is not 16UC1 (millimetres) or 32FC1 (metres)");
  }
  if (color.header.frame_id != depth.header.frame_id) {
    throw InputError("depth frame_id '" + depth.header.frame_id + "' differs from colour frame_id '" +
                     color.header.frame_id + "': subscribe to depth registered to the colour camera");
  }
  if (!info.header.frame_id.empty() && info.header.frame_id != color.header.frame_id) {  // empty: a hand-made info
    throw InputError("camera_info frame_id '" + info.header.frame_id + "' differs from colour frame_id '" +
                     color.header.frame_id + "': it calibrates another camera (subscribe to the colour camera's)");
  }
  const image_geometry::PinholeCameraModel model = cameraModelOf(info);
  const cv::Size expected = model.reducedResolution();
  if (static_cast<uint32_t>(expected.width) != color.width || static_cast<uint32_t>(expected.height) != color.height) {
    const bool reduced = expected != model.fullResolution();
    throw InputError("camera_info is for " + std::to_string(expected.width) + "x" + std::to_string(expected.height) +
                     (reduced ? " (after its binning and roi)" : "") + " but the colour image is " +
                     std::to_string(color.width) + "x" + std::to_string(color.height));
  }
  checkBuffer(color, "colour");
  checkBuffer(depth, "depth");
  const bool rgb_order = color.encoding == enc::RGB8 || color.encoding == enc::RGBA8;
  try {
    return RgbdFrame(imageOf(color, cvTypeOf(color.encoding)), imageOf(depth, cvTypeOf(depth.encoding)),
                     intrinsicsOf(model), rgb_order ? ColorOrder::RGB : ColorOrder::BGR);
  } catch (const cv::Exception& e) {  // none is known; a node must not die of one
    throw InputError(std::string("image message cannot be read: ") + e.err);
  }
}

double secondsBetween(const ros::Time& later, const ros::Time& earlier) { return later.toSec() - earlier.toSec(); }

std::string checkOneMoment(const std_msgs::Header& color, const std_msgs::Header& depth, double max_interval) {
  const double apart = std::abs(secondsBetween(color.stamp, depth.stamp));
  char text[200];
  if (max_interval > 0.0 && apart > max_interval) {
    std::snprintf(text, sizeof text,
                  "colour and depth are stamped %.3f s apart, more than ~approximate_sync_max_interval (%g s)", apart,
                  max_interval);
    throw InputError(text);
  }
  if (apart <= kOneMomentInterval) return "";
  std::snprintf(text, sizeof text,
                "colour and depth are stamped %.3f s apart: the depth is of another moment (a bound on it, "
                "~approximate_sync_max_interval, skips such pairs)",
                apart);
  return text;
}

KeypointArrayPtr toMessage(const Features& features, const std_msgs::Header& header,
                           const sensor_msgs::CameraInfo& info) {
  auto message = boost::make_shared<KeypointArray>();
  message->header = header;
  message->camera_info = info;
  message->descriptor_type = "RISAS";
  message->descriptor_dim = static_cast<uint32_t>(features.descriptors.cols);
  message->descriptor_layout = features.descriptor_layout;
  message->keypoints.resize(features.keypoints.size());
  for (size_t i = 0; i < features.keypoints.size(); ++i) {
    const cv::KeyPoint& k = features.keypoints[i];
    Keypoint& m = message->keypoints[i];
    m.x = k.pt.x;
    m.y = k.pt.y;
    m.size = k.size;
    m.angle = k.angle;
    m.response = k.response;
    m.octave = k.octave;
    m.class_id = k.class_id;
    if (i < features.geometry.size()) {
      const KeypointGeometry& g = features.geometry[i];
      m.point.x = g.point.x;
      m.point.y = g.point.y;
      m.point.z = g.point.z;
      m.normal = {g.normal[0], g.normal[1], g.normal[2]};
      m.support_radius = g.support_radius;
    }
  }
  const cv::Mat rows = features.descriptors.isContinuous() ? features.descriptors : features.descriptors.clone();
  message->descriptors.assign(rows.ptr<float>(), rows.ptr<float>() + rows.total());
  return message;
}

sensor_msgs::PointCloud2Ptr toPointCloud(const Features& features, const std_msgs::Header& header) {
  auto cloud = boost::make_shared<sensor_msgs::PointCloud2>();
  cloud->header = header;
  sensor_msgs::PointCloud2Modifier modifier(*cloud);
  const auto f32 = sensor_msgs::PointField::FLOAT32;
  modifier.setPointCloud2Fields(7, "x", 1, f32, "y", 1, f32, "z", 1, f32, "response", 1, f32, "normal_x", 1, f32,
                                "normal_y", 1, f32, "normal_z", 1, f32);
  modifier.resize(features.geometry.size());
  cloud->height = 1;
  cloud->width = static_cast<uint32_t>(features.geometry.size());
  cloud->is_dense = true;
  // PointCloud2Iterator's constructor reads data.front(): undefined on an
  // empty cloud (a frame without keypoints; UBSan names it).
  if (features.geometry.empty()) return cloud;
  sensor_msgs::PointCloud2Iterator<float> out(*cloud, "x");
  for (size_t i = 0; i < features.geometry.size(); ++i, ++out) {
    const risas::KeypointGeometry& g = features.geometry[i];
    const float values[] = {g.point.x, g.point.y, g.point.z, features.keypoints[i].response,
                            g.normal[0], g.normal[1], g.normal[2]};
    std::copy(std::begin(values), std::end(values), &out[0]);
  }
  return cloud;
}

Features fromMessage(const KeypointArray& message) {
  const size_t n = message.keypoints.size();
  if (message.descriptors.size() != n * message.descriptor_dim) {
    throw InputError("KeypointArray holds " + std::to_string(message.descriptors.size()) + " descriptor values, not " +
                     std::to_string(n) + " x " + std::to_string(message.descriptor_dim));
  }
  // A keypoint's point may be NaN (no depth there: the odometry skips it);
  // its pixel and its descriptor may not, since the matcher and the
  // overlays would take a NaN as a place or a distance.
  for (size_t i = 0; i < n; ++i) {
    const Keypoint& m = message.keypoints[i];
    if (!std::isfinite(m.x) || !std::isfinite(m.y)) {
      throw InputError("KeypointArray keypoint " + std::to_string(i) + " is at a non-finite pixel");
    }
  }
  const auto bad = std::find_if(message.descriptors.begin(), message.descriptors.end(),
                                [](float v) { return !std::isfinite(v); });
  if (bad != message.descriptors.end()) {
    const size_t at = static_cast<size_t>(bad - message.descriptors.begin());
    throw InputError("KeypointArray descriptor of keypoint " + std::to_string(at / message.descriptor_dim) +
                     " holds a non-finite value");
  }
  Features features;
  for (const Keypoint& m : message.keypoints) {
    features.keypoints.emplace_back(cv::Point2f(m.x, m.y), m.size, m.angle, m.response, m.octave, m.class_id);
    features.geometry.push_back({cv::Point3f(m.point.x, m.point.y, m.point.z),
                                 cv::Vec3f(m.normal[0], m.normal[1], m.normal[2]), m.support_radius});
  }
  features.descriptors = cv::Mat(static_cast<int>(n), static_cast<int>(message.descriptor_dim), CV_32F,
                                 const_cast<float*>(message.descriptors.data()))
                             .clone();
  features.descriptor_layout = message.descriptor_layout;
  return features;
}

geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T) { return tf2::eigenToTransform(T).transform; }

Eigen::Isometry3d fromTransform(const geometry_msgs::Transform& t) {
  geometry_msgs::Transform unit = t;  // tf2 does not normalise the quaternion
  unit.rotation = tf2::toMsg(Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).normalized());
  return tf2::transformToEigen(unit);
}

geometry_msgs::Pose toPose(const Eigen::Isometry3d& T) {
  const geometry_msgs::Transform t = toTransform(T);
  geometry_msgs::Pose p;
  p.position.x = t.translation.x;
  p.position.y = t.translation.y;
  p.position.z = t.translation.z;
  p.orientation = t.rotation;
  return p;
}

nav_msgs::Odometry toOdometry(const risas::OdometryResult& result, const std_msgs::Header& header,
                              const std::string& child_frame_id, const Eigen::Isometry3d& base_T_camera,
                              double lost_variance, double dt) {
  nav_msgs::Odometry odom;
  odom.header = header;
  odom.child_frame_id = child_frame_id;
  const Eigen::Isometry3d camera_T_base = base_T_camera.inverse();
  odom.pose.pose = toPose(base_T_camera * result.world_T_camera * camera_T_base);
  const Eigen::Matrix<double, 6, 6> covariance =
      result.tracked ? risas::rotateCovariance(risas::composeCovariance(result.world_T_camera, result.covariance,
                                                                        camera_T_base,
                                                                        Eigen::Matrix<double, 6, 6>::Zero()),
                                               base_T_camera.linear())
                     : result.covariance;
  risas::Twist twist;
  if (result.motion_tracked && risas::isTwistInterval(dt)) {
    twist = risas::transformTwist(risas::twistFromMotion(result.previous_T_camera, result.motion_covariance, dt),
                                  base_T_camera);
  } else {
    twist.covariance = lost_variance * Eigen::Matrix<double, 6, 6>::Identity();
  }
  odom.twist.twist = tf2::toMsg(twist.velocity);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      odom.pose.covariance[static_cast<size_t>(6 * i + j)] = covariance(i, j);
      odom.twist.covariance[static_cast<size_t>(6 * i + j)] = twist.covariance(i, j);
    }
  }
  return odom;
}

void checkImageTransport(const std::string& transport, const std::string& parameter, bool depth,
                         const std::vector<std::string>& loadable) {
  static const std::vector<std::string> lossy = {"compressed", "theora", "ffmpeg", "h264", "h265"};
  if (depth && std::find(lossy.begin(), lossy.end(), transport) != lossy.end()) {
    throw std::invalid_argument(parameter + " '" + transport +
                                "' is lossy and would change depth values: use raw or compressedDepth");
  }
  std::string installed;
  for (const std::string& name : loadable) {
    const std::string base = name.substr(name.rfind('/') + 1);  // "image_transport/raw" -> "raw"
    if (base == transport) return;
    installed += (installed.empty() ? "" : ", ") + base;
  }
  throw std::invalid_argument(parameter + " '" + transport + "' is not installed (installed: " +
                              (installed.empty() ? "none" : installed) + ")");
}

namespace {

// A text value as given, unless it begins with '{', '}', '[' or ']': FileStorage's
// writer takes such a text for a structure mark (a value "}" closed the
// section early, and the writer then crashed in its destructor: the fuzz
// driver found it), so it gets a space in front. The reader refuses it
// either way, as it is no number and no flag.
std::string asFileText(const std::string& value) {
  return !value.empty() && std::strchr("{}[]", value.front()) ? " " + value : value;
}

// Whether FileStorage writes `name` as a key and reads it back as given: a
// letter or '_' first, then letters, digits, '_' and '-'.
bool isFileKey(const std::string& name) {
  const auto letter = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; };
  return !name.empty() && letter(name.front()) &&
         std::all_of(name.begin(), name.end(),
                     [&](char c) { return letter(c) || std::isdigit(static_cast<unsigned char>(c)) || c == '-'; });
}

// The RISAS sections of `sections` as the text of a parameter file: flags as
// 0 or 1, numbers and text as given, lists and maps as text (which the
// reader refuses as not a number). Whatever is refused here is refused
// before the FileStorage exists: one destroyed halfway through writing to
// memory crashed in its destructor (OpenCV 4.6; the fuzz driver found it).
std::string asParameterFile(XmlRpc::XmlRpcValue& sections) {
  RisasParams names;
  std::vector<const char*> present;
  visitSections(names, [&](const char* section, const auto&) {
    if (sections.getType() != XmlRpc::XmlRpcValue::TypeStruct || !sections.hasMember(section)) return;
    XmlRpc::XmlRpcValue& fields = sections[section];
    if (fields.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
      throw InputError(std::string("~") + section + " must hold parameters (~" + section + "/<name>)");
    }
    for (auto& field : fields) {
      if (!isFileKey(field.first)) {
        throw InputError(std::string("~") + section + "/" + field.first +
                         " is no parameter name (a letter or '_', then letters, digits, '_' and '-')");
      }
    }
    present.push_back(section);
  });
  cv::FileStorage text(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  for (const char* section : present) {
    text << section << "{";
    for (auto& [name, value] : sections[section]) {
      switch (value.getType()) {
        case XmlRpc::XmlRpcValue::TypeBoolean: text << name << (static_cast<bool>(value) ? 1 : 0); break;
        case XmlRpc::XmlRpcValue::TypeInt: text << name << static_cast<int>(value); break;
        case XmlRpc::XmlRpcValue::TypeDouble: text << name << static_cast<double>(value); break;
        case XmlRpc::XmlRpcValue::TypeString: text << name << asFileText(value); break;
        default: text << name << "(a list or a map)"; break;
      }
    }
    text << "}";
  }
  return text.releaseAndGetString();
}

}  // namespace

RisasParams paramsFromXmlRpc(XmlRpc::XmlRpcValue& sections) {
  // Read as a parameter file by RisasParams::read, so that a file and the
  // server share one reader and cannot disagree on a name, a type or a range.
  RisasParams params;
  try {
    const cv::FileStorage file(asParameterFile(sections), cv::FileStorage::READ | cv::FileStorage::MEMORY);
    params.read(file.root());
  } catch (const cv::Exception& e) {  // a name or value FileStorage cannot write or read back
    throw InputError("parameters not readable as a parameter file: " + e.err);
  }
  params.validate();
  return params;
}

RisasParams paramsFromServer(const ros::NodeHandle& nh) {
  XmlRpc::XmlRpcValue sections;
  RisasParams names;
  visitSections(names, [&](const char* section, const auto&) {
    XmlRpc::XmlRpcValue fields;
    if (nh.getParam(section, fields)) sections[section] = fields;
  });
  return paramsFromXmlRpc(sections);
}

}  // namespace risas_ros

#include "risas/rgbd_frame.hpp"

#include "risas/errors.hpp"

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <limits>
#include <sstream>

namespace risas {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

template <typename T>
struct DepthTraits;

template <>
struct DepthTraits<uint16_t> {  // millimetres, 0 = no measurement (65.535 m at most: within kMaxDepth)
  static float toMetres(uint16_t raw) { return raw == 0 ? kNaN : raw * 0.001f; }
};

template <>
struct DepthTraits<float> {  // metres, NaN/inf/<=0/beyond kMaxDepth = no measurement
  static float toMetres(float raw) { return raw > 0.0f && raw <= RgbdFrame::kMaxDepth ? raw : kNaN; }
};

template <typename T>
cv::Mat convertDepth(const cv::Mat& depth) {
  cv::Mat metres(depth.size(), CV_32FC1);
  for (int r = 0; r < depth.rows; ++r) {
    const T* in = depth.ptr<T>(r);
    float* out = metres.ptr<float>(r);
    for (int c = 0; c < depth.cols; ++c) out[c] = DepthTraits<T>::toMetres(in[c]);
  }
  return metres;
}

}  // namespace

std::string describeType(const cv::Mat& m) {
  std::ostringstream s;
  s << (m.depth() == CV_8U ? "8-bit" : m.depth() == CV_16U ? "16-bit" : m.depth() == CV_32F ? "32-bit float" : "")
    << (m.depth() == CV_8U || m.depth() == CV_16U || m.depth() == CV_32F ? ", " : "") << m.channels()
    << (m.channels() == 1 ? " channel" : " channels") << " (" << cv::typeToString(m.type()) << ")";
  return s.str();
}

cv::Mat depthToMetres(const cv::Mat& depth) {
  if (depth.empty()) throw InputError("depth image is empty");
  switch (depth.type()) {
    case CV_16UC1: return convertDepth<uint16_t>(depth);
    case CV_32FC1: return convertDepth<float>(depth);
    default:
      throw InputError("depth image must be CV_16UC1 (millimetres) or CV_32FC1 (metres), got " +
                       describeType(depth));
  }
}

RgbdFrame::RgbdFrame(const cv::Mat& color, const cv::Mat& depth, const Intrinsics& intrinsics,
                     ColorOrder order)
    : intrinsics_(intrinsics) {
  if (color.empty()) throw InputError("colour image is empty");
  if (depth.empty()) throw InputError("depth image is empty");
  if (color.rows < kMinSide || color.cols < kMinSide) {
    throw InputError("frame of " + std::to_string(color.cols) + "x" + std::to_string(color.rows) +
                     " pixels is too small: at least " + std::to_string(kMinSide) + "x" + std::to_string(kMinSide));
  }
  if (color.size() != depth.size()) {
    std::ostringstream msg;
    msg << "colour (" << color.cols << "x" << color.rows << ") and depth (" << depth.cols << "x"
        << depth.rows << ") differ in size; they must be registered to the same pixel grid";
    throw InputError(msg.str());
  }
  const bool rgb = order == ColorOrder::RGB;
  switch (color.type()) {
    case CV_8UC1: gray_ = color.clone(); break;
    case CV_8UC3: cv::cvtColor(color, gray_, rgb ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY); break;
    case CV_8UC4: cv::cvtColor(color, gray_, rgb ? cv::COLOR_RGBA2GRAY : cv::COLOR_BGRA2GRAY); break;
    default:
      throw InputError("colour image must be 8-bit with 1, 3 or 4 channels, got " + describeType(color));
  }
  intrinsics_.validate(color.size());
  depth_ = depthToMetres(depth);
  // A frame with no depth at all is a sensor fault, not a scene: say so.
  if (cv::countNonZero(depth_ == depth_) == 0) {
    throw InputError("depth image has no valid pixel (depth in (0, " + std::to_string(static_cast<int>(kMaxDepth)) +
                     "] m)");
  }
}

}  // namespace risas

// The ROS layer's checks and conversions, without a master.
#include "synthetic_fixtures.hpp"

#include "risas/errors.hpp"
#include "risas/params.hpp"
#include "risas/ros/conversions.hpp"
#include "risas/ros/log_throttle.hpp"
#include "risas/ros/node_params.hpp"
#include "risas/ros/reconfigure.hpp"

#include <risas/RisasDescriptorConfig.h>
#include <risas/RisasDetectorConfig.h>
#include <risas/RisasMatchConfig.h>

#include <cv_bridge/cv_bridge.h>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgproc.hpp>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace risas_ros {
namespace {

namespace enc = sensor_msgs::image_encodings;

struct Messages {
  sensor_msgs::Image rgb, depth;
  sensor_msgs::CameraInfo info;
};

Messages render() {
  const risas::SyntheticRender r =
      risas::SyntheticScene::demo().render(risas::syntheticIntrinsics(), risas::test::kVga, risas::test::demoCamera());
  std_msgs::Header header;
  header.frame_id = "camera_rgb_optical_frame";
  header.stamp = ros::Time(100.0);
  cv::Mat rgb;
  cv::cvtColor(r.bgr, rgb, cv::COLOR_BGR2RGB);
  Messages m{*cv_bridge::CvImage(header, enc::RGB8, rgb).toImageMsg(),
             *cv_bridge::CvImage(header, enc::TYPE_16UC1, r.depth_mm).toImageMsg(),
             cameraInfoFromIntrinsics(risas::syntheticIntrinsics(), risas::test::kVga)};
  m.info.header = header;
  return m;
}

template <class F>
void expectInputError(F&& f, const std::string& fragment) {
  try {
    f();
    FAIL() << "expected InputError containing '" << fragment << "'";
  } catch (const risas::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Conversions, AcceptsEveryDocumentedEncoding) {
  const Messages m = render();
  const RgbdFrame reference = frameFromMessages(m.rgb, m.depth, m.info);
  EXPECT_EQ(reference.size(), risas::test::kVga);
  EXPECT_NEAR(risas::syntheticIntrinsics().fx, reference.intrinsics().fx, 1e-9);

  const cv::Mat rgb = cv_bridge::toCvCopy(m.rgb)->image;
  for (const auto& [encoding, code] : {std::pair<std::string, int>{enc::BGR8, cv::COLOR_RGB2BGR},
                                       {enc::RGBA8, cv::COLOR_RGB2RGBA}, {enc::BGRA8, cv::COLOR_RGB2BGRA},
                                       {enc::MONO8, cv::COLOR_RGB2GRAY}}) {
    cv::Mat converted;
    cv::cvtColor(rgb, converted, code);
    const sensor_msgs::Image image = *cv_bridge::CvImage(m.rgb.header, encoding, converted).toImageMsg();
    const RgbdFrame frame = frameFromMessages(image, m.depth, m.info);
    EXPECT_LE(cv::norm(frame.gray(), reference.gray(), cv::NORM_INF), 1.0) << encoding;  // same grey
  }
  // 32FC1 metres gives the same depth as 16UC1 millimetres.
  cv::Mat metres;
  cv_bridge::toCvCopy(m.depth)->image.convertTo(metres, CV_32F, 0.001);
  const RgbdFrame in_metres =
      frameFromMessages(m.rgb, *cv_bridge::CvImage(m.depth.header, enc::TYPE_32FC1, metres).toImageMsg(), m.info);
  cv::Mat diff = cv::abs(in_metres.depth() - reference.depth());
  EXPECT_LT(cv::norm(diff, cv::NORM_INF, reference.depth() == reference.depth()), 1e-6);
}

// The image with each row padded to `step` bytes, its bytes reversed per
// channel value when big_endian.
sensor_msgs::Image repacked(const sensor_msgs::Image& image, uint32_t step, bool big_endian) {
  sensor_msgs::Image out = image;
  const size_t row = image.width * static_cast<size_t>(enc::numChannels(image.encoding) * enc::bitDepth(image.encoding) / 8);
  const size_t value = enc::bitDepth(image.encoding) / 8;
  out.step = step;
  out.is_bigendian = big_endian;
  out.data.assign(static_cast<size_t>(step) * image.height, 0xAB);
  for (uint32_t r = 0; r < image.height; ++r) {
    const uint8_t* in = &image.data[r * image.step];
    uint8_t* to = &out.data[r * step];
    for (size_t b = 0; b < row; b += value) {
      for (size_t k = 0; k < value; ++k) to[b + k] = in[b + (big_endian ? value - 1 - k : k)];
    }
  }
  return out;
}

void expectSameFrame(const RgbdFrame& a, const RgbdFrame& b) {
  EXPECT_EQ(cv::norm(a.gray(), b.gray(), cv::NORM_INF), 0.0);
  cv::Mat da = a.depth().clone(), db = b.depth().clone();
  cv::patchNaNs(da, -1.0), cv::patchNaNs(db, -1.0);
  EXPECT_EQ(cv::norm(da, db, cv::NORM_INF), 0.0);
}

TEST(Conversions, OddStepsAndBigEndianDepthAreReadAsThePackedImage) {
  // Issue 20: a step that is no multiple of the pixel size made cv::Mat
  // throw, uncaught, and took the nodelet manager down; a big-endian 16UC1
  // was misreported as CV_8UC2.
  const Messages m = render();
  const RgbdFrame reference = frameFromMessages(m.rgb, m.depth, m.info);
  expectSameFrame(reference, frameFromMessages(m.rgb, repacked(m.depth, 2 * 640 + 1, false), m.info));
  expectSameFrame(reference, frameFromMessages(repacked(m.rgb, 3 * 640 + 5, false), m.depth, m.info));
  expectSameFrame(reference, frameFromMessages(m.rgb, repacked(m.depth, 2 * 640, true), m.info));
  expectSameFrame(reference, frameFromMessages(m.rgb, repacked(m.depth, 2 * 640 + 3, true), m.info));

  cv::Mat metres;
  cv_bridge::toCvCopy(m.depth)->image.convertTo(metres, CV_32F, 0.001);
  const sensor_msgs::Image depth32 = *cv_bridge::CvImage(m.depth.header, enc::TYPE_32FC1, metres).toImageMsg();
  const RgbdFrame reference32 = frameFromMessages(m.rgb, depth32, m.info);
  expectSameFrame(reference32, frameFromMessages(m.rgb, repacked(depth32, 4 * 640 + 2, false), m.info));
  expectSameFrame(reference32, frameFromMessages(m.rgb, repacked(depth32, 4 * 640 + 2, true), m.info));
}

TEST(Conversions, RejectsEverythingElseNamingTheProblem) {
  const Messages good = render();
  Messages m = good;
  m.rgb.encoding = "rgb16";
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "'rgb16'");
  m = good;
  m.depth.encoding = enc::MONO8;
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "depth image encoding 'mono8'");
  m = good;
  m.depth.header.frame_id = "camera_depth_optical_frame";
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "differs from colour frame_id");
  m = good;
  m.info.header.frame_id = "camera_depth_optical_frame";  // the unregistered depth camera's calibration
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); },
                   "camera_info frame_id 'camera_depth_optical_frame' differs from colour frame_id "
                   "'camera_rgb_optical_frame': it calibrates another camera");
  m.info.header.frame_id.clear();  // a hand-made camera_info without a frame is taken
  EXPECT_NO_THROW(frameFromMessages(m.rgb, m.depth, m.info));
  m = good;
  cv::Mat small(240, 320, CV_16UC1, cv::Scalar(1000));
  m.depth = *cv_bridge::CvImage(good.depth.header, enc::TYPE_16UC1, small).toImageMsg();
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "differ in size");
  m = good;
  m.info.width = 320;
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "camera_info is for 320x480");
  m = good;
  m.info.K.fill(0.0);
  m.info.P.fill(0.0);
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "not calibrated");
  m = good;
  m.info.P[0] = -5.0;
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "focal lengths");
  m = good;
  m.rgb.data.resize(100);  // step x height no longer matches the buffer
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "colour image message is malformed");
  m = good;
  m.depth.step = 100;  // shorter than a row of 640 16-bit pixels
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "depth image message is malformed");
  m = good;  // rows of no pixels, padded by part of a pixel (UBSan saw a copy to no buffer)
  m.rgb.width = m.depth.width = m.info.width = 0;
  m.rgb.step = m.depth.step = 1;
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "colour image is empty");
}

// Colour and depth of two moments: beyond the bound refused with the
// interval and the parameter that bounds it (0: no bound); beyond 0.02 s a
// warning; within it nothing.
TEST(Conversions, ColourAndDepthOfTwoMomentsAreWarnedOfOrRefused) {
  std_msgs::Header colour, depth;
  colour.stamp = ros::Time(100.0);
  depth.stamp = ros::Time(100.015);
  EXPECT_EQ(checkOneMoment(colour, depth, 0.0), "");
  EXPECT_EQ(checkOneMoment(depth, colour, 0.02), "");
  expectInputError([&] { checkOneMoment(colour, depth, 0.01); }, "stamped 0.015 s apart");  // a bound below 0.02 s
  depth.stamp = ros::Time(100.1);
  EXPECT_EQ(checkOneMoment(colour, depth, 0.0),
            "colour and depth are stamped 0.100 s apart: the depth is of another moment (a bound on it, "
            "~approximate_sync_max_interval, skips such pairs)");
  EXPECT_NE(checkOneMoment(depth, colour, 0.2), "");
  expectInputError([&] { checkOneMoment(colour, depth, 0.05); },
                   "colour and depth are stamped 0.100 s apart, more than ~approximate_sync_max_interval (0.05 s)");
  expectInputError([&] { checkOneMoment(depth, colour, 0.05); }, "stamped 0.100 s apart");
  // Beyond ros::Duration's 2^31 s (an unset stamp against one past 2038):
  // said as any other gap, where ros::Time's difference would throw.
  depth.stamp = ros::Time(3000000000u, 0u);
  colour.stamp = ros::Time(0u, 0u);
  EXPECT_NE(checkOneMoment(colour, depth, 0.0).find("3000000000.000 s apart"), std::string::npos);
  expectInputError([&] { checkOneMoment(depth, colour, 0.05); }, "3000000000.000 s apart");
  EXPECT_EQ(secondsBetween(depth.stamp, colour.stamp), 3e9);
}

// A camera calibrated with distortion: the rectified image's projection P
// differs from the raw image's K, and rectified images need P (as
// image_geometry::PinholeCameraModel says). Without P, K is what there is.
TEST(Conversions, IntrinsicsOfARectifiedImageAreItsProjectionNotK) {
  Messages m = render();
  m.info.distortion_model = "plumb_bob";
  m.info.D = {-0.28, 0.07, 0.001, -0.0005, 0.0};
  m.info.K = {580.0, 0.0, 322.0, 0.0, 578.0, 243.0, 0.0, 0.0, 1.0};
  m.info.P = {525.0, 0.0, 319.5, 0.0, 0.0, 526.0, 239.5, 0.0, 0.0, 0.0, 1.0, 0.0};
  const risas::Intrinsics from_p = frameFromMessages(m.rgb, m.depth, m.info).intrinsics();
  EXPECT_EQ(from_p.fx, 525.0);
  EXPECT_EQ(from_p.fy, 526.0);
  EXPECT_EQ(from_p.cx, 319.5);
  EXPECT_EQ(from_p.cy, 239.5);
  m.info.P.fill(0.0);
  const risas::Intrinsics from_k = frameFromMessages(m.rgb, m.depth, m.info).intrinsics();
  EXPECT_EQ(from_k.fx, 580.0);
  EXPECT_EQ(from_k.cy, 243.0);
  m.info.P = {525.0, 3.0, 319.5, 0.0, 0.0, 526.0, 239.5, 0.0, 0.0, 0.0, 1.0, 0.0};  // skewed
  expectInputError([&] { frameFromMessages(m.rgb, m.depth, m.info); }, "not a pinhole");
}

// image_proc's crop_decimate and drivers' reduced modes publish the
// calibration's full-resolution K and P with binning and roi set: the image
// is the reduced one, and its intrinsics are image_geometry's for it.
TEST(Conversions, BinnedAndCroppedImagesAreReadWithTheirReducedIntrinsics) {
  const Messages full = render();
  const auto reduced = [](const sensor_msgs::Image& image, const cv::Rect& roi, int binning) {
    const cv_bridge::CvImagePtr cv = cv_bridge::toCvCopy(image);
    cv::resize(cv->image(roi), cv->image, cv::Size(), 1.0 / binning, 1.0 / binning, cv::INTER_NEAREST);
    return *cv->toImageMsg();
  };
  const risas::Intrinsics vga = risas::syntheticIntrinsics();

  Messages decimated = full;
  decimated.rgb = reduced(full.rgb, cv::Rect(0, 0, 640, 480), 2);
  decimated.depth = reduced(full.depth, cv::Rect(0, 0, 640, 480), 2);
  decimated.info.binning_x = decimated.info.binning_y = 2;
  const risas::Intrinsics half = frameFromMessages(decimated.rgb, decimated.depth, decimated.info).intrinsics();
  EXPECT_DOUBLE_EQ(half.fx, vga.fx / 2);
  EXPECT_DOUBLE_EQ(half.fy, vga.fy / 2);
  EXPECT_DOUBLE_EQ(half.cx, vga.cx / 2);
  EXPECT_DOUBLE_EQ(half.cy, vga.cy / 2);
  EXPECT_DOUBLE_EQ(intrinsicsFromCameraInfo(decimated.info).fx, vga.fx / 2);

  Messages cropped = full;
  const cv::Rect roi(100, 60, 320, 240);
  cropped.rgb = reduced(full.rgb, roi, 1);
  cropped.depth = reduced(full.depth, roi, 1);
  cropped.info.roi.x_offset = 100, cropped.info.roi.y_offset = 60;
  cropped.info.roi.width = 320, cropped.info.roi.height = 240;
  const risas::Intrinsics window = frameFromMessages(cropped.rgb, cropped.depth, cropped.info).intrinsics();
  EXPECT_DOUBLE_EQ(window.fx, vga.fx);
  EXPECT_DOUBLE_EQ(window.cx, vga.cx - 100);
  EXPECT_DOUBLE_EQ(window.cy, vga.cy - 60);

  // K alone is reduced the same way; a full-size image with binning set is
  // the mismatch it is, named as such.
  decimated.info.P.fill(0.0);
  EXPECT_DOUBLE_EQ(frameFromMessages(decimated.rgb, decimated.depth, decimated.info).intrinsics().cx, vga.cx / 2);
  Messages not_decimated = full;
  not_decimated.info.binning_x = not_decimated.info.binning_y = 2;
  expectInputError([&] { frameFromMessages(not_decimated.rgb, not_decimated.depth, not_decimated.info); },
                   "camera_info is for 320x240 (after its binning and roi) but the colour image is 640x480");
}

// The odometry nodelet's message. The camera as the child: the result as it
// is. A base 0.5 m from the camera: the base's pose through the static
// transform, and a covariance that is the scatter of the base's pose when
// the camera's is drawn from the result's (Monte Carlo), 1° of the camera's
// heading uncertainty moving the base by its lever arm.
TEST(Conversions, OdometryMessagesCarryTheCamerasCovarianceToTheBase) {
  risas::OdometryResult r;
  r.tracked = true;
  r.world_T_camera = Eigen::Translation3d(0.4, -0.2, 1.5) * Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 2, 2).normalized());
  Eigen::Matrix<double, 6, 1> sd;
  sd << 0.002, 0.001, 0.003, 0.017, 0.004, 0.009;
  r.covariance = sd.cwiseAbs2().asDiagonal();
  std_msgs::Header header;
  header.frame_id = "odom";
  header.stamp = ros::Time(12.5);

  const nav_msgs::Odometry camera = toOdometry(r, header, "camera_rgb_optical_frame", Eigen::Isometry3d::Identity(), 9999.0, 0.1);
  EXPECT_EQ(camera.header.frame_id, "odom");
  EXPECT_EQ(camera.header.stamp, header.stamp);
  EXPECT_EQ(camera.child_frame_id, "camera_rgb_optical_frame");
  EXPECT_NEAR(camera.pose.pose.position.x, 0.4, 1e-12);
  for (int i = 0; i < 36; ++i) EXPECT_DOUBLE_EQ(camera.pose.covariance[static_cast<size_t>(i)], r.covariance(i / 6, i % 6));
  for (int i = 0; i < 6; ++i) EXPECT_EQ(camera.twist.covariance[static_cast<size_t>(7 * i)], 9999.0);

  // base_link: x forward, z up; the optical frame z forward, 0.5 m ahead.
  Eigen::Matrix3d optical;
  optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Eigen::Isometry3d base_T_camera = Eigen::Translation3d(0.5, 0.05, 0.3) * Eigen::Quaterniond(optical);
  const nav_msgs::Odometry base = toOdometry(r, header, "base_link", base_T_camera, 9999.0, 0.1);
  EXPECT_EQ(base.child_frame_id, "base_link");
  const auto poseOf = [](const geometry_msgs::Pose& p) {
    geometry_msgs::Transform t;
    t.translation.x = p.position.x, t.translation.y = p.position.y, t.translation.z = p.position.z;
    t.rotation = p.orientation;
    return fromTransform(t);
  };
  const Eigen::Isometry3d odom_T_base = base_T_camera * r.world_T_camera * base_T_camera.inverse();
  EXPECT_TRUE(poseOf(base.pose.pose).isApprox(odom_T_base, 1e-9));
  std::mt19937 rng(4);
  std::normal_distribution<double> unit(0.0, 1.0);
  Eigen::Matrix<double, 6, 6> scatter = Eigen::Matrix<double, 6, 6>::Zero();
  const int draws = 4000;
  for (int k = 0; k < draws; ++k) {
    Eigen::Matrix<double, 6, 1> d;
    for (int i = 0; i < 6; ++i) d(i) = sd(i) * unit(rng);
    Eigen::Isometry3d drawn = r.world_T_camera;
    drawn.translation() += d.head<3>();
    drawn.linear() = Eigen::AngleAxisd(d.tail<3>().norm(), d.tail<3>().normalized()) * r.world_T_camera.linear();
    const Eigen::Isometry3d moved = base_T_camera * drawn * base_T_camera.inverse();
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = moved.translation() - odom_T_base.translation();
    const Eigen::AngleAxisd turn(moved.linear() * odom_T_base.linear().transpose());
    e.tail<3>() = turn.angle() * turn.axis();
    scatter += e * e.transpose() / draws;
  }
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(base.pose.covariance[static_cast<size_t>(7 * i)] / scatter(i, i), 1.0, 0.15) << "axis " << i;
  }
  // The camera's position variance merely turned into odom's axes (the
  // nodelet before) is less than half the base's.
  const double turned_only = r.covariance.topLeftCorner(3, 3).trace();
  EXPECT_LT(turned_only, 0.5 * scatter.topLeftCorner(3, 3).trace());

  // Lost: the pose held, the lost variances as they are.
  r.tracked = false;
  r.covariance = 9999.0 * Eigen::Matrix<double, 6, 6>::Identity();
  const nav_msgs::Odometry lost = toOdometry(r, header, "base_link", base_T_camera, 9999.0, 0.1);
  EXPECT_TRUE(poseOf(lost.pose.pose).isApprox(odom_T_base, 1e-9));
  for (int i = 0; i < 36; ++i) EXPECT_EQ(lost.pose.covariance[static_cast<size_t>(i)], i % 7 == 0 ? 9999.0 : 0.0);
}

// The twist: the camera moving 2 cm along its optical axis in 1/30 s is a
// base driving forward at 0.6 m/s; a turn of the camera about its y axis
// (down) is the base turning right, its origin 0.5 m behind the camera
// swinging left. Without a motion or a time, the twist is unknown.
TEST(Conversions, OdometryMessagesCarryTheFrameToFrameMotionAsTheBasesTwist) {
  Eigen::Matrix3d optical;
  optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Eigen::Isometry3d base_T_camera = Eigen::Translation3d(0.5, 0.0, 0.0) * Eigen::Quaterniond(optical);
  std_msgs::Header header;
  header.frame_id = "odom";
  const double dt = 1.0 / 30.0;
  risas::OdometryResult r;
  r.tracked = r.motion_tracked = true;
  r.previous_T_camera = Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, 0.02));
  Eigen::Matrix<double, 6, 1> sd;
  sd << 0.001, 0.002, 0.003, 0.0005, 0.001, 0.0002;
  r.motion_covariance = sd.cwiseAbs2().asDiagonal();
  const nav_msgs::Odometry forward = toOdometry(r, header, "base_link", base_T_camera, 9999.0, dt);
  EXPECT_NEAR(forward.twist.twist.linear.x, 0.6, 1e-9);
  EXPECT_NEAR(forward.twist.twist.linear.y, 0.0, 1e-9);
  EXPECT_NEAR(forward.twist.twist.angular.z, 0.0, 1e-9);
  // In the base's axes, over dt^2: the camera's z (3 mm) is the base's x;
  // its x (1 mm) the base's -y, to which the yaw (the camera's y turn, 1
  // mrad) adds its swing of the base 0.5 m behind, and 1 cm more: the
  // logarithm's, half the 2 cm travelled turning with it.
  const auto expectVariance = [&](size_t index, double variance) {
    EXPECT_NEAR(forward.twist.covariance[index], variance / (dt * dt), 1e-3 * variance / (dt * dt)) << index;
  };
  expectVariance(0, 0.003 * 0.003);
  expectVariance(7, 0.001 * 0.001 + 0.51 * 0.51 * 0.001 * 0.001);
  expectVariance(35, 0.001 * 0.001);

  const double turn = 0.9 * dt;  // rad/s about the camera's y, which points down
  r.previous_T_camera = Eigen::Isometry3d(Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitY()));
  const nav_msgs::Odometry turning = toOdometry(r, header, "base_link", base_T_camera, 9999.0, dt);
  EXPECT_NEAR(turning.twist.twist.angular.z, -0.9, 1e-9);  // about the base's z, down being -z: a right turn
  EXPECT_NEAR(turning.twist.twist.linear.y, 0.5 * 0.9, 1e-9);  // v = t x w: the base's origin swings left
  const nav_msgs::Odometry camera = toOdometry(r, header, "camera_rgb_optical_frame", Eigen::Isometry3d::Identity(), 9999.0, dt);
  EXPECT_NEAR(camera.twist.twist.angular.y, 0.9, 1e-9);
  EXPECT_NEAR(camera.twist.twist.linear.x, 0.0, 1e-9);

  for (const double bad : {0.0, -dt, std::nan("")}) {
    const nav_msgs::Odometry unknown = toOdometry(r, header, "base_link", base_T_camera, 9999.0, bad);
    EXPECT_EQ(unknown.twist.twist.angular.z, 0.0) << bad;
    for (int i = 0; i < 36; ++i) EXPECT_EQ(unknown.twist.covariance[static_cast<size_t>(i)], i % 7 == 0 ? 9999.0 : 0.0);
  }
  r.motion_tracked = false;
  const nav_msgs::Odometry first = toOdometry(r, header, "base_link", base_T_camera, 9999.0, dt);
  EXPECT_EQ(first.twist.twist.linear.x, 0.0);
  EXPECT_EQ(first.twist.covariance[0], 9999.0);
}

TEST(Transports, LossyDepthAndUninstalledTransportsAreRefusedByName) {
  const std::vector<std::string> debian = {"image_transport/raw"};
  const std::vector<std::string> wifi = {"image_transport/raw", "compressed_image_transport/compressed",
                                         "compressed_depth_image_transport/compressedDepth"};
  EXPECT_NO_THROW(checkImageTransport("raw", "image_transport", false, debian));
  EXPECT_NO_THROW(checkImageTransport("raw", "depth_image_transport", true, debian));
  EXPECT_NO_THROW(checkImageTransport("compressed", "image_transport", false, wifi));
  EXPECT_NO_THROW(checkImageTransport("compressedDepth", "depth_image_transport", true, wifi));
  const auto message = [](const std::string& transport, bool depth, const std::vector<std::string>& loadable) {
    try {
      checkImageTransport(transport, depth ? "depth_image_transport" : "image_transport", depth, loadable);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message("compressed", true, wifi),
            "depth_image_transport 'compressed' is lossy and would change depth values: use raw or compressedDepth");
  EXPECT_NE(message("theora", true, wifi).find("'theora' is lossy"), std::string::npos);
  EXPECT_EQ(message("compressedDepth", true, debian),
            "depth_image_transport 'compressedDepth' is not installed (installed: raw)");
  EXPECT_EQ(message("jpeg", false, wifi),
            "image_transport 'jpeg' is not installed (installed: raw, compressed, compressedDepth)");
}

TEST(Conversions, PointCloudHoldsEachKeypointsPointResponseAndNormalInPclsFieldNames) {
  const Messages m = render();
  const risas::Features f = risas::Risas().extract(frameFromMessages(m.rgb, m.depth, m.info));
  ASSERT_GT(f.keypoints.size(), 100u);
  const sensor_msgs::PointCloud2Ptr cloud = toPointCloud(f, m.rgb.header);
  EXPECT_EQ(cloud->header.frame_id, "camera_rgb_optical_frame");
  EXPECT_EQ(cloud->header.stamp, m.rgb.header.stamp);
  ASSERT_EQ(cloud->width * cloud->height, f.keypoints.size());
  EXPECT_EQ(cloud->data.size(), size_t(cloud->row_step) * cloud->height);
  std::vector<std::string> names;
  for (const auto& field : cloud->fields) names.push_back(field.name);
  EXPECT_EQ(names, (std::vector<std::string>{"x", "y", "z", "response", "normal_x", "normal_y", "normal_z"}));
  sensor_msgs::PointCloud2ConstIterator<float> x(*cloud, "x"), response(*cloud, "response"), nz(*cloud, "normal_z");
  for (size_t i = 0; i < f.keypoints.size(); ++i, ++x, ++response, ++nz) {
    EXPECT_EQ(x[0], f.geometry[i].point.x);
    EXPECT_EQ(x[1], f.geometry[i].point.y);
    EXPECT_EQ(x[2], f.geometry[i].point.z);
    EXPECT_EQ(*response, f.keypoints[i].response);
    EXPECT_EQ(*nz, f.geometry[i].normal[2]);
  }
  EXPECT_EQ(toPointCloud(risas::Features(), m.rgb.header)->width, 0u);
}

TEST(Conversions, KeypointArrayRoundTripsAndWrapsAsAMat) {
  const Messages m = render();
  const risas::Features f = risas::Risas().extract(frameFromMessages(m.rgb, m.depth, m.info));
  ASSERT_GT(f.keypoints.size(), 100u);
  const KeypointArrayPtr message = toMessage(f, m.rgb.header, m.info);
  EXPECT_EQ(message->descriptor_type, "RISAS");
  const int dimension = risas::RisasParams().descriptor.dimension();
  EXPECT_EQ(message->descriptor_dim, static_cast<uint32_t>(dimension));
  EXPECT_EQ(message->descriptor_layout, risas::RisasParams().descriptor.layout());
  EXPECT_EQ(message->descriptors.size(), f.keypoints.size() * dimension);
  EXPECT_EQ(message->header.stamp, m.rgb.header.stamp);
  // The documented zero-copy view is the same matrix.
  const cv::Mat view(static_cast<int>(message->keypoints.size()), dimension, CV_32F, message->descriptors.data());
  EXPECT_EQ(cv::norm(view, f.descriptors, cv::NORM_INF), 0.0);

  const risas::Features back = fromMessage(*message);
  ASSERT_EQ(back.keypoints.size(), f.keypoints.size());
  EXPECT_EQ(back.descriptor_layout, f.descriptor_layout);
  for (size_t i = 0; i < f.keypoints.size(); ++i) {
    EXPECT_EQ(back.keypoints[i].pt, f.keypoints[i].pt);
    EXPECT_EQ(back.keypoints[i].angle, f.keypoints[i].angle);
    EXPECT_EQ(back.geometry[i].point, f.geometry[i].point);
    EXPECT_EQ(back.geometry[i].normal, f.geometry[i].normal);
  }
  // A keypoint without depth is kept; a NaN pixel or descriptor value is
  // refused, naming the keypoint.
  message->keypoints[2].point.z = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(std::isnan(fromMessage(*message).geometry[2].point.z));
  KeypointArray no_pixel = *message;
  no_pixel.keypoints[3].x = std::numeric_limits<float>::infinity();
  expectInputError([&] { fromMessage(no_pixel); }, "keypoint 3 is at a non-finite pixel");
  KeypointArray no_descriptor = *message;
  no_descriptor.descriptors[static_cast<size_t>(5 * dimension + 1)] = std::numeric_limits<float>::quiet_NaN();
  expectInputError([&] { fromMessage(no_descriptor); }, "descriptor of keypoint 5 holds a non-finite value");
  message->descriptors.pop_back();
  EXPECT_THROW(fromMessage(*message), risas::InputError);
}

// Each .cfg field against its namesake in params_fields.hpp: it exists, and
// its default and range are the library's. Returns the names checked.
template <class Config, class Section>
std::vector<std::string> expectCfgMatchesLibrary(Section defaults) {
  const Config cfg_default = Config::__getDefault__();
  const Config cfg_min = Config::__getMin__();
  const Config cfg_max = Config::__getMax__();
  std::vector<std::string> names;
  for (const auto& d : Config::__getParamDescriptions__()) {
    names.push_back(d->name);
    bool found = false;
    visitFields(defaults, [&](const char* name, auto& value, auto... range) {
      if (d->name != name) return;
      found = true;
      boost::any def, lo, hi;
      d->getValue(cfg_default, def);
      d->getValue(cfg_min, lo);
      d->getValue(cfg_max, hi);
      const auto number = [](const boost::any& a) {
        if (const int* i = boost::any_cast<int>(&a)) return double(*i);
        if (const bool* b = boost::any_cast<bool>(&a)) return double(*b);
        return boost::any_cast<double>(a);
      };
      EXPECT_EQ(number(def), double(value)) << d->name << ": .cfg default differs from the library's";
      if constexpr (sizeof...(range) == 2) {
        const double bounds[] = {double(range)...};
        EXPECT_EQ(number(lo), bounds[0]) << d->name << ": .cfg minimum differs from params_fields.hpp";
        EXPECT_EQ(number(hi), bounds[1]) << d->name << ": .cfg maximum differs from params_fields.hpp";
      }
    });
    EXPECT_TRUE(found) << d->name << " in the .cfg is no field of its section in params_fields.hpp";
  }
  return names;
}

TEST(Reconfigure, CfgNamesDefaultsAndRangesAreTheLibrarys) {
  const RisasParams defaults;
  const auto detector = expectCfgMatchesLibrary<risas::RisasDetectorConfig>(defaults.detector);
  const auto descriptor = expectCfgMatchesLibrary<risas::RisasDescriptorConfig>(defaults.descriptor);
  const auto match = expectCfgMatchesLibrary<risas::RisasMatchConfig>(defaults.match);
  EXPECT_EQ(detector, (std::vector<std::string>{"tau", "response_threshold", "nms_radius", "max_keypoints",
                                                "min_keypoints", "grid_cols", "grid_rows", "gray_sigma", "dp_sigma",
                                                "window_sigma"}));
  EXPECT_EQ(descriptor, (std::vector<std::string>{"gamma", "n_pie", "n_bin", "n_vec", "n_ring", "shape_weight",
                                                  "rho_threshold", "support_radius", "gradient_orientation",
                                                  "soft_binning", "sample_blur", "grey_noise"}));
  EXPECT_EQ(match, (std::vector<std::string>{"ratio", "cross_check"}));
}

// The README says config/odometry.yaml's detector can be set live: every
// field the preset changes is on ~detector, so its Config carries the whole
// preset onto the defaults.
TEST(Reconfigure, TheOdometryPresetsDetectorCanBeSetLive) {
  const risas::DetectorParams preset = RisasParams::load(RISAS_SOURCE_DIR "/config/odometry.yaml").detector;
  const risas::DetectorParams live = applyConfig(toConfig<risas::RisasDetectorConfig>(preset), risas::DetectorParams());
  const auto values = [](risas::DetectorParams p) {
    std::vector<double> v;
    visitFields(p, [&](const char*, auto& field, auto...) { v.push_back(static_cast<double>(field)); });
    return v;
  };
  EXPECT_NE(values(preset), values(risas::DetectorParams()));
  EXPECT_EQ(values(live), values(preset));
}

TEST(Reconfigure, ConfigsMapToTheirSectionsBothWays) {
  RisasParams params;
  params.detector.tau = 0.25;
  params.descriptor.n_bin = 16;
  params.descriptor.n_ring = 2;
  params.match.cross_check = true;
  const auto descriptor = toConfig<risas::RisasDescriptorConfig>(params.descriptor);
  EXPECT_EQ(descriptor.n_bin, 16);
  EXPECT_EQ(descriptor.n_ring, 2);
  EXPECT_EQ(toConfig<risas::RisasDetectorConfig>(params.detector).tau, 0.25);
  params.detector.grid_cols = 1;
  EXPECT_EQ(toConfig<risas::RisasDetectorConfig>(params.detector).grid_cols, 1);
  EXPECT_TRUE(toConfig<risas::RisasMatchConfig>(params.match).cross_check);

  risas::RisasDescriptorConfig changed = descriptor;
  changed.n_vec = 3;
  changed.rho_threshold = 0.5;
  changed.gradient_orientation = false;
  changed.sample_blur = 1.25;
  const risas::DescriptorParams applied = applyConfig(changed, params.descriptor);
  EXPECT_EQ(applied.n_vec, 3);
  EXPECT_EQ(applied.rho_threshold, 0.5);
  EXPECT_FALSE(applied.gradient_orientation);
  EXPECT_EQ(applied.sample_blur, 1.25);
  EXPECT_TRUE(applied.soft_binning);  // left as the config had it
  EXPECT_EQ(applied.n_bin, 16);
  EXPECT_EQ(applied.patch_radius, params.descriptor.patch_radius);  // not reconfigurable: kept
}

// A parameter file as `rosparam load` puts it on the server: YAML's ints as
// ints (the shipped files write flags as 0 and 1), its reals as doubles.
XmlRpc::XmlRpcValue asRosparamLoadsIt(const std::string& path) {
  const cv::FileStorage file(path, cv::FileStorage::READ);
  XmlRpc::XmlRpcValue sections;
  for (const cv::FileNode& section : file.root()) {
    for (const cv::FileNode& field : section) {
      XmlRpc::XmlRpcValue& value = sections[section.name()][field.name()];
      if (field.isInt()) {
        value = static_cast<int>(field);
      } else {
        value = static_cast<double>(field);
      }
    }
  }
  return sections;
}

std::string paramsText(const RisasParams& p) {
  cv::FileStorage fs(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  p.write(fs);
  return fs.releaseAndGetString();
}

// Each shipped file reaches a node through rosparam as it reaches the tools:
// config/paper.yaml's flags (0 and 1, ints on the server) included.
TEST(ParamsFromServer, TheShippedFilesGiveWhatTheToolsRead) {
  for (const char* name : {"risas.yaml", "paper.yaml", "odometry.yaml"}) {
    const std::string path = std::string(RISAS_SOURCE_DIR "/config/") + name;
    XmlRpc::XmlRpcValue sections = asRosparamLoadsIt(path);
    EXPECT_EQ(paramsText(paramsFromXmlRpc(sections)), paramsText(RisasParams::load(path))) << name;
  }
  XmlRpc::XmlRpcValue flags;
  flags["descriptor"]["soft_binning"] = false;
  flags["descriptor"]["shape_orientation"] = true;
  flags["detector"]["max_keypoints"] = 1000.0;  // a whole number, as a double
  flags["queue_size"] = 5;                      // a node's own parameter: not looked at
  const RisasParams read = paramsFromXmlRpc(flags);
  EXPECT_FALSE(read.descriptor.soft_binning);
  EXPECT_TRUE(read.descriptor.shape_orientation);
  EXPECT_EQ(read.detector.max_keypoints, 1000);
}

// What a parameter file refuses, the server's parameters are refused for,
// in one line naming the field: a typo no longer leaves the default
// silently in place.
TEST(ParamsFromServer, TyposFractionsBadFlagsAndTextAreRefusedByName) {
  const auto refusal = [](const char* section, const char* name, XmlRpc::XmlRpcValue value) {
    XmlRpc::XmlRpcValue sections;
    sections[section][name] = value;
    try {
      paramsFromXmlRpc(sections);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal("detector", "max_keypoint", 1000).find("'detector.max_keypoint'"), std::string::npos);
  EXPECT_NE(refusal("detector", "max_keypoints", 2.5).find("detector.max_keypoints = 2.5 is not a whole number"),
            std::string::npos);
  EXPECT_NE(refusal("descriptor", "soft_binning", 2).find("descriptor.soft_binning is a flag"), std::string::npos);
  EXPECT_NE(refusal("detector", "tau", std::string("high")).find("detector.tau is not a number"), std::string::npos);
  EXPECT_NE(refusal("detector", "tau", 2.0).find("detector.tau = 2 is outside [0, 1]"), std::string::npos);
  XmlRpc::XmlRpcValue list;
  list[0] = 1;
  EXPECT_NE(refusal("detector", "tau", list).find("detector.tau is not a number"), std::string::npos);
  EXPECT_NE(refusal("detector", "max keypoints!", 1).find("~detector/max keypoints! is no parameter name"),
            std::string::npos);  // no name of a file: refused, not thrown past
  XmlRpc::XmlRpcValue one_bad;  // a section written, the next one refused (the writer crashed when destroyed)
  one_bad["geometry"]["normal_radius"] = 5;
  one_bad["descriptor"] = XmlRpc::XmlRpcValue();
  EXPECT_THROW(paramsFromXmlRpc(one_bad), std::invalid_argument);
  // Text that FileStorage's writer would take for a structure mark (a "}"
  // closed the section early and crashed the node).
  for (const char* mark : {"}", "]", "{", "[", "{:", "}x"}) {
    EXPECT_NE(refusal("descriptor", "max_radius_px", std::string(mark)).find("descriptor.max_radius_px is not a number"),
              std::string::npos)
        << mark;
  }
  XmlRpc::XmlRpcValue not_a_section;
  not_a_section["detector"] = 5;
  EXPECT_THROW(paramsFromXmlRpc(not_a_section), std::invalid_argument);
}

// A node's own parameters: what was given, or one line naming it, where
// roscpp's NodeHandle::param would fall back to the default in silence
// (`_approximate_sync:=0` is an int on the server, not a bool).
TEST(NodeParams, GivenValuesAreTakenAndWrongOnesRefusedByName) {
  const auto refusal = [](auto read, XmlRpc::XmlRpcValue value) {
    try {
      read(value);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  XmlRpc::XmlRpcValue zero(0), one(1), yes(true), whole(5.0), text(std::string("depth"));
  EXPECT_FALSE(flagValue("~approximate_sync", zero));
  EXPECT_TRUE(flagValue("~approximate_sync", one));
  EXPECT_TRUE(flagValue("~approximate_sync", yes));
  EXPECT_EQ(intValue("~queue_size", whole, 1, 1000), 5);
  EXPECT_EQ(intValue("~queue_size", one, 1, 1000), 1);
  EXPECT_DOUBLE_EQ(numberValue("~rate", one, 0.01, 1000.0), 1.0);
  EXPECT_EQ(textValue("~frame_id", text), "depth");

  const auto flag = [](XmlRpc::XmlRpcValue& v) { return flagValue("~approximate_sync", v); };
  const auto queue = [](XmlRpc::XmlRpcValue& v) { return intValue("~queue_size", v, 1, 1000); };
  const auto rate = [](XmlRpc::XmlRpcValue& v) { return numberValue("~rate", v, 0.01, 1000.0); };
  const auto frame = [](XmlRpc::XmlRpcValue& v) { return textValue("~frame_id", v); };
  EXPECT_EQ(refusal(flag, 2), "~approximate_sync must be a flag: true, false, 0 or 1 (got <value><i4>2</i4></value>)");
  EXPECT_NE(refusal(flag, std::string("yes")).find("~approximate_sync must be a flag"), std::string::npos);
  EXPECT_NE(refusal(queue, 0).find("~queue_size must be a whole number in [1, 1000]"), std::string::npos);
  EXPECT_NE(refusal(queue, 2.5).find("~queue_size must be a whole number"), std::string::npos);
  EXPECT_NE(refusal(queue, std::string("5")).find("~queue_size must be a whole number"), std::string::npos);
  EXPECT_NE(refusal(rate, 0.0).find("~rate must be a number in [0.01, 1000]"), std::string::npos);
  EXPECT_NE(refusal(rate, std::numeric_limits<double>::quiet_NaN()).find("~rate must be"), std::string::npos);
  XmlRpc::XmlRpcValue serial(1208180007);  // <param name="device_id" value="1208180007"/>
  EXPECT_EQ(textValue("~device_id", serial), "1208180007");
  EXPECT_NE(refusal(frame, 2.5).find("~frame_id must be text"), std::string::npos);
  EXPECT_NE(refusal(frame, true).find("~frame_id must be text"), std::string::npos);
}

// Frame parameters are tf frame ids, and a node's frames differ: tf2 refuses
// an empty id, one with a leading '/', and a frame that is its own parent.
TEST(NodeParams, FrameIdsAreTfsAndANodesFramesDiffer) {
  const auto refusal = [](XmlRpc::XmlRpcValue value) {
    try {
      frameIdValue("~odom_frame_id", value);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  XmlRpc::XmlRpcValue odom(std::string("odom")), nested(std::string("robot1/odom"));
  EXPECT_EQ(frameIdValue("~odom_frame_id", odom), "odom");
  EXPECT_EQ(frameIdValue("~odom_frame_id", nested), "robot1/odom");
  EXPECT_EQ(refusal(std::string("/odom")),
            "~odom_frame_id must be a tf frame id: not empty, no leading '/' (got <value>/odom</value>)");
  EXPECT_NE(refusal(std::string("")).find("~odom_frame_id must be a tf frame id"), std::string::npos);
  EXPECT_NE(refusal(3.5).find("~odom_frame_id must be text"), std::string::npos);

  EXPECT_NO_THROW(requireDistinctFrames({{"~odom_frame_id", "odom"}, {"~base_frame_id", ""}}));
  EXPECT_NO_THROW(requireDistinctFrames({{"~a", "x"}, {"~b", "y"}, {"~c", "z"}}));
  try {
    requireDistinctFrames({{"~frame_id", "cam"}, {"~world_frame", "world"}, {"~truth_frame_id", "cam"}});
    FAIL() << "one frame named twice was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "~frame_id and ~truth_frame_id name one frame 'cam': they must differ");
  }
}

// The names under a node's private namespace that nothing reads: each
// first-level name once, below the namespace only (not a sibling sharing its
// prefix), whatever lies under a name that is read.
TEST(NodeParams, NamesNothingReadsAreFound) {
  const std::vector<std::string> server = {"/risas/queue_size",         "/risas/aproximate_sync",
                                           "/risas/detector/tau",       "/risas/detectr/tau",
                                           "/risas/detectr/max_keypoints", "/risas/image/compressed/jpeg_quality",
                                           "/risas_odometry/publish_tf", "/risas2/anything",
                                           "/rosdistro",                "/run_id"};
  const std::set<std::string> read = {"queue_size", "detector", "image"};
  EXPECT_EQ(unreadNames(server, "/risas", read), (std::vector<std::string>{"aproximate_sync", "detectr"}));
  EXPECT_EQ(unreadNames(server, "/risas_odometry", {"publish_tf"}), std::vector<std::string>{});
  EXPECT_EQ(unreadNames(server, "/elsewhere", read), std::vector<std::string>{});
  EXPECT_EQ(unreadNames({"/ns/node/a", "/ns/node/b/c"}, "/ns/node", {"b"}), std::vector<std::string>{"a"});
}

TEST(LogThrottle, ReportsNewProblemsAtOnceAndRepeatsRarely) {
  ros::Time::init();
  LogThrottle throttle(60.0);
  EXPECT_TRUE(throttle.shouldLog("depth encoding 'mono8'"));
  EXPECT_FALSE(throttle.shouldLog("depth encoding 'mono8'"));
  EXPECT_TRUE(throttle.shouldLog("sizes differ"));
  // Two faults alternating frame by frame are each held back, not reported every frame.
  EXPECT_FALSE(throttle.shouldLog("depth encoding 'mono8'"));
  EXPECT_FALSE(throttle.shouldLog("sizes differ"));
  // It keeps the last 64 problems: the oldest of 64 new ones pushes out "depth encoding".
  for (int i = 0; i < 63; ++i) EXPECT_TRUE(throttle.shouldLog("stamped " + std::to_string(i) + " s apart"));
  EXPECT_FALSE(throttle.shouldLog("sizes differ"));
  EXPECT_TRUE(throttle.shouldLog("depth encoding 'mono8'"));
  LogThrottle quick(0.0);
  EXPECT_TRUE(quick.shouldLog("x"));
  EXPECT_TRUE(quick.shouldLog("x"));
}

}  // namespace
}  // namespace risas_ros

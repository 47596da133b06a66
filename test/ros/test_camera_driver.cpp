// The camera nodelet's logic with a fake device: registration and sync flags,
// streaming, encodings, frame_ids, stamps, intrinsics, errors. No hardware.
#include "risas/ros/conversions.hpp"
#include "risas/ros/openni2_device.hpp"
#include "risas/ros/rgbd_camera_driver.hpp"
#include "risas/synthetic_scene.hpp"

#include <image_geometry/pinhole_camera_model.h>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace risas_ros {
namespace {

// A device that renders the synthetic scene, with a device clock of its own.
struct FakeDevice : RgbdDevice {
  struct Log {
    bool registration = false, frame_sync = false, streaming = false;
    int starts = 0, stops = 0;
    StreamMode mode;
  };
  Log* log;
  bool registration_supported = true;
  uint64_t clock_us = 5'000'000;
  double clock_rate = 1.0;  // device clock speed relative to real time
  int reads_until_gone = -1;
  bool time_out = false;

  explicit FakeDevice(Log* l) : log(l) {}
  std::string description() const override { return "FakeDevice at fake://1"; }
  bool supportsRegistration() const override { return registration_supported; }
  void setRegistration(bool enabled) override { log->registration = enabled; }
  void setFrameSync(bool enabled) override { log->frame_sync = enabled; }
  void start(const StreamMode& mode) override {
    log->mode = mode;
    log->streaming = true;
    ++log->starts;
  }
  void stop() override {
    log->streaming = false;
    ++log->stops;
  }
  bool read(DeviceFrame& color, DeviceFrame& depth, double) override {
    if (reads_until_gone == 0) throw DeviceError(description() + " was disconnected");
    if (reads_until_gone > 0) --reads_until_gone;
    if (time_out) return false;
    static const risas::SyntheticRender r = risas::SyntheticScene::demo().render(
        risas::syntheticIntrinsics(), cv::Size(640, 480), risas::SyntheticScene::demoCamera(0.0));
    cv::cvtColor(r.bgr, color.image, cv::COLOR_BGR2RGB);
    depth.image = r.depth_mm.clone();
    color.timestamp_us = clock_us;
    depth.timestamp_us = clock_us + 700;  // depth a little after colour, as on a PS1080
    clock_us += static_cast<uint64_t>(33333 * clock_rate);
    return true;
  }
  double horizontalFov() const override { return 1.0225; }  // an Xtion's 58.6 degrees
  double verticalFov() const override { return 0.7944; }
};

struct Harness {
  FakeDevice::Log log;
  FakeDevice* device = nullptr;
  ros::Time now{1000.0};
  std::unique_ptr<RgbdCameraDriver> driver;

  explicit Harness(CameraSettings settings = CameraSettings(), bool supports_registration = true) {
    auto fake = std::make_unique<FakeDevice>(&log);
    fake->registration_supported = supports_registration;
    device = fake.get();
    driver = std::make_unique<RgbdCameraDriver>(std::move(fake), settings, [this] { return now; });
  }
  // One frame period of real time passes, then a read.
  std::optional<CameraMessages> tick() {
    now += ros::Duration(1.0 / 30.0);
    return driver->next(0.5);
  }
};

TEST(CameraDriver, RegistersDepthAndSyncsFramesWhenTheDeviceCan) {
  Harness h;
  EXPECT_TRUE(h.log.registration);
  EXPECT_TRUE(h.log.frame_sync);
  EXPECT_TRUE(h.driver->registered());
  EXPECT_TRUE(h.driver->warning().empty());
  EXPECT_EQ(h.driver->depthTopic(), "depth_registered/image_raw");
}

TEST(CameraDriver, PublishesUnregisteredDepthSeparatelyWhenTheDeviceCannotRegister) {
  Harness h(CameraSettings(), false);
  EXPECT_FALSE(h.log.registration);
  EXPECT_FALSE(h.driver->registered());
  EXPECT_NE(h.driver->warning().find("cannot register depth to colour"), std::string::npos) << h.driver->warning();
  EXPECT_EQ(h.driver->depthTopic(), "depth/image_raw");
  h.driver->start();
  const auto m = h.tick();
  ASSERT_TRUE(m);
  EXPECT_EQ(m->depth->header.frame_id, "camera_depth_optical_frame");
}

TEST(CameraDriver, StreamsOnlyBetweenStartAndStop) {
  Harness h;
  EXPECT_FALSE(h.driver->next(0.1)) << "frames before start";
  EXPECT_FALSE(h.log.streaming);
  h.driver->start();
  h.driver->start();  // idempotent
  EXPECT_TRUE(h.log.streaming);
  EXPECT_EQ(h.log.starts, 1);
  EXPECT_EQ(h.log.mode.width, 640);
  EXPECT_EQ(h.log.mode.fps, 30);
  EXPECT_TRUE(h.tick());
  h.driver->stop();
  EXPECT_FALSE(h.log.streaming);
  EXPECT_EQ(h.log.stops, 1);
  EXPECT_FALSE(h.driver->next(0.1));
}

TEST(CameraDriver, MessagesHaveOpenNIEncodingsFrameIdsAndOneStampPerPair) {
  Harness h;
  h.driver->start();
  const auto first = h.tick();
  const auto second = h.tick();
  ASSERT_TRUE(first && second);
  EXPECT_EQ(first->color->encoding, "rgb8");
  EXPECT_EQ(first->depth->encoding, "16UC1");
  EXPECT_EQ(first->color->width, 640u);
  EXPECT_EQ(first->depth->height, 480u);
  EXPECT_EQ(first->color->header.frame_id, "camera_rgb_optical_frame");
  EXPECT_EQ(first->depth->header.frame_id, "camera_rgb_optical_frame");
  EXPECT_EQ(first->color->header.stamp, first->depth->header.stamp);
  EXPECT_NEAR((second->color->header.stamp - first->color->header.stamp).toSec(), 0.033333, 1e-6)
      << "stamps follow the device clock";
  // What the camera publishes is what RisasNodelet accepts.
  const RgbdFrame frame = frameFromMessages(*first->color, *first->depth, h.driver->cameraInfoFromFov());
  EXPECT_EQ(frame.size(), cv::Size(640, 480));
}

TEST(CameraDriver, StampsFollowTheDeviceClockButNeverDriftAway) {
  Harness h;
  h.device->clock_rate = 1.1;  // a device clock 10 % fast
  h.driver->start();
  for (int i = 0; i < 300; ++i) {
    const auto m = h.tick();
    ASSERT_TRUE(m);
    EXPECT_LE(std::abs((m->color->header.stamp - h.now).toSec()), 0.05) << "frame " << i;
  }
}

// A device clock that jumps by more than ros::Duration holds (2^31 s: a
// garbage timestamp, or one counted from another epoch) re-anchors the
// stamps to ROS time instead of throwing out of the camera's thread.
TEST(CameraDriver, ADeviceClockJumpingAnyDistanceReanchorsTheStamps) {
  Harness h;
  h.driver->start();
  ASSERT_TRUE(h.tick());
  for (const uint64_t jump : {uint64_t{1} << 62, uint64_t{0}, ~uint64_t{0} - 1000000}) {
    h.device->clock_us = jump;
    const auto m = h.tick();
    ASSERT_TRUE(m);
    EXPECT_LE(std::abs((m->color->header.stamp - h.now).toSec()), 0.05) << "device clock " << jump;
    const auto next = h.tick();
    ASSERT_TRUE(next);
    EXPECT_NEAR((next->color->header.stamp - m->color->header.stamp).toSec(), 0.033333, 1e-6)
        << "the device clock followed again after " << jump;
  }
}

TEST(CameraDriver, IntrinsicsFromTheFieldsOfView) {
  Harness h;
  const sensor_msgs::CameraInfo info = h.driver->cameraInfoFromFov();
  EXPECT_NEAR(info.K[0], 320.0 / std::tan(1.0225 / 2.0), 1e-9);
  EXPECT_NEAR(info.K[4], 240.0 / std::tan(0.7944 / 2.0), 1e-9);
  EXPECT_NEAR(info.K[0], 570.3, 1.0);  // an Xtion's nominal focal length
  EXPECT_DOUBLE_EQ(info.K[2], 319.5);
  EXPECT_DOUBLE_EQ(info.K[5], 239.5);
  EXPECT_EQ(info.header.frame_id, "camera_rgb_optical_frame");
}

// A calibration made at 640x480 serves the 320x240 mode through binning
// (read by risas as the reduced image's intrinsics); one of another size
// does not serve at all.
TEST(CameraDriver, ACalibrationServesTheModesThatDivideItsSize) {
  const sensor_msgs::CameraInfo vga = cameraInfoFromIntrinsics(risas::Intrinsics(570.0, 571.0, 318.0, 241.0), cv::Size(640, 480));
  Harness at_vga;
  const auto same = at_vga.driver->cameraInfoFromCalibration(vga);
  ASSERT_TRUE(same);
  EXPECT_EQ(same->binning_x, 0u);
  EXPECT_EQ(same->K, vga.K);
  EXPECT_EQ(same->header.frame_id, "camera_rgb_optical_frame");

  CameraSettings qvga_mode;
  qvga_mode.mode = {320, 240, 30};
  Harness at_qvga(qvga_mode);
  const auto binned = at_qvga.driver->cameraInfoFromCalibration(vga);
  ASSERT_TRUE(binned);
  EXPECT_EQ(binned->binning_x, 2u);
  EXPECT_EQ(binned->binning_y, 2u);
  const risas::Intrinsics K = intrinsicsFromCameraInfo(*binned);
  EXPECT_DOUBLE_EQ(K.fx, 285.0);
  EXPECT_DOUBLE_EQ(K.cy, 120.5);

  sensor_msgs::CameraInfo odd = vga;
  odd.width = 800, odd.height = 600;
  EXPECT_FALSE(at_vga.driver->cameraInfoFromCalibration(odd));
  odd.width = 1280, odd.height = 720;  // width a multiple, height not the same one
  EXPECT_FALSE(at_vga.driver->cameraInfoFromCalibration(odd));
  CameraSettings larger;
  larger.mode = {1280, 960, 30};
  EXPECT_FALSE(Harness(larger).driver->cameraInfoFromCalibration(vga));
}

// openni2.launch rectifies the 320x240 mode with image_proc's rectify, which
// undistorts through image_geometry's PinholeCameraModel::rectifyImage with
// the binned camera_info above. A distorted 640x480 calibration must then
// rectify the binned image as it rectifies the full one, reduced.
TEST(CameraDriver, ABinnedCalibrationRectifiesAsTheFullOneReduced) {
  sensor_msgs::CameraInfo vga = cameraInfoFromIntrinsics(risas::Intrinsics(525.0, 525.0, 319.5, 239.5), cv::Size(640, 480));
  vga.distortion_model = "plumb_bob";
  vga.D = {0.2, -0.4, 0.001, -0.002, 0.1};  // strong enough to move the corners by tens of pixels
  vga.P = {520.0, 0.0, 320.0, 0.0, 0.0, 520.0, 240.0, 0.0, 0.0, 0.0, 1.0, 0.0};
  CameraSettings qvga_mode;
  qvga_mode.mode = {320, 240, 30};
  const auto binned = Harness(qvga_mode).driver->cameraInfoFromCalibration(vga);
  ASSERT_TRUE(binned);

  cv::Mat raw(480, 640, CV_8UC1);
  for (int v = 0; v < raw.rows; ++v) {
    for (int u = 0; u < raw.cols; ++u) raw.at<uchar>(v, u) = ((u / 20 + v / 20) % 2) ? 220 : 20;  // 20 px squares
  }
  cv::Mat raw_reduced;
  cv::resize(raw, raw_reduced, cv::Size(320, 240), 0, 0, cv::INTER_AREA);

  image_geometry::PinholeCameraModel full, reduced;
  full.fromCameraInfo(vga);
  reduced.fromCameraInfo(*binned);
  cv::Mat rectified_full, rectified_reduced, expected;
  full.rectifyImage(raw, rectified_full, cv::INTER_LINEAR);
  reduced.rectifyImage(raw_reduced, rectified_reduced, cv::INTER_LINEAR);
  ASSERT_EQ(rectified_reduced.size(), cv::Size(320, 240));
  cv::resize(rectified_full, expected, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
  cv::Mat difference;
  cv::absdiff(rectified_reduced, expected, difference);
  EXPECT_LT(cv::mean(difference)[0], 2.0);  // measured 0.47: the squares' edges resampled at two sizes
  cv::absdiff(raw_reduced, expected, difference);
  EXPECT_GT(cv::mean(difference)[0], 20.0);  // the distortion does move the pattern (measured 67)

  const cv::Point2d corner_full = full.rectifyPoint(cv::Point2d(100.0, 80.0));
  const cv::Point2d corner_reduced = reduced.rectifyPoint(cv::Point2d(50.0, 40.0));
  EXPECT_NEAR(corner_reduced.x, corner_full.x / 2.0, 0.01);
  EXPECT_NEAR(corner_reduced.y, corner_full.y / 2.0, 0.01);
  EXPECT_GT(cv::norm(corner_full - cv::Point2d(100.0, 80.0)), 5.0);
}

TEST(CameraDriver, TimeoutsAndALostDeviceAreReported) {
  Harness h;
  h.driver->start();
  h.device->time_out = true;
  EXPECT_FALSE(h.tick());
  h.device->time_out = false;
  h.device->reads_until_gone = 1;
  EXPECT_TRUE(h.tick());
  try {
    h.tick();
    FAIL() << "a lost device went unreported";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("fake://1 was disconnected"), std::string::npos) << e.what();
  }
}

TEST(CameraDriver, RejectsAnImpossibleMode) {
  CameraSettings settings;
  settings.mode.fps = 0;
  EXPECT_THROW(Harness h(settings), DeviceError);
}

// ~device_id "#N" picks the N-th device: N is read whole and checked, so a
// typo is refused rather than read as its leading digits ("#2x" was device
// 2) and a huge N is refused rather than overflowing (atoi's undefined
// behaviour).
TEST(OpenNI2DeviceId, NumberIsWholeAndFromOne) {
  EXPECT_EQ(deviceNumberOf("#1"), 1);
  EXPECT_EQ(deviceNumberOf("#12"), 12);
  for (const char* bad : {"", "#", "#0", "#-1", "#+2", "# 2", "#2x", "#2.0", "#99999999999", "2"}) {
    try {
      deviceNumberOf(bad);
      ADD_FAILURE() << bad << " was taken";
    } catch (const DeviceError& e) {
      EXPECT_EQ(std::string(e.what()), std::string("device_id ") + bad + " is not #N, the N-th device found (N = 1, 2, ...)");
    }
  }
}

}  // namespace
}  // namespace risas_ros

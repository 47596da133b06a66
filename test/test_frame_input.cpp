// Every bad input of a frame, intrinsics or parameters gives the documented
// error naming the problem; good inputs in both depth encodings agree.
#include "risas/descriptor.hpp"
#include "risas/detector.hpp"
#include "risas/errors.hpp"
#include "risas/geometry.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace risas {
namespace {

const Intrinsics kK(500.0, 510.0, 32.0, 24.0);

cv::Mat colour() { return cv::Mat(48, 64, CV_8UC3, cv::Scalar(10, 20, 30)); }
cv::Mat depthMm() { return cv::Mat(48, 64, CV_16UC1, cv::Scalar(1000)); }

// Expects construction to throw InputError whose message contains `fragment`.
template <class F>
void expectInputError(F&& make, const std::string& fragment) {
  try {
    make();
    FAIL() << "expected InputError containing '" << fragment << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(FrameInput, AcceptsGreyBgrAndBgraWithMillimetreDepth) {
  for (int type : {CV_8UC1, CV_8UC3, CV_8UC4}) {
    const RgbdFrame frame(cv::Mat(48, 64, type, cv::Scalar::all(100)), depthMm(), kK);
    EXPECT_EQ(frame.gray().type(), CV_8UC1);
    EXPECT_EQ(frame.gray().at<uchar>(5, 5), 100);
    EXPECT_FLOAT_EQ(frame.depth().at<float>(5, 5), 1.0f);
  }
}

TEST(FrameInput, RgbAndBgrOrderGiveTheirOwnGrey) {
  cv::Mat red(48, 64, CV_8UC3, cv::Scalar(0, 0, 255));  // red in BGR
  const RgbdFrame as_bgr(red, depthMm(), kK, ColorOrder::BGR);
  const RgbdFrame as_rgb(red, depthMm(), kK, ColorOrder::RGB);
  EXPECT_EQ(as_bgr.gray().at<uchar>(0, 0), 76);  // 0.299 * 255
  EXPECT_EQ(as_rgb.gray().at<uchar>(0, 0), 29);  // 0.114 * 255
}

TEST(FrameInput, MillimetreAndMetreDepthAgreeAndMarkMissingAsNaN) {
  cv::Mat mm = depthMm();
  mm.at<uint16_t>(3, 4) = 0;
  mm.at<uint16_t>(6, 7) = 1234;
  cv::Mat m(48, 64, CV_32FC1, cv::Scalar(1.0f));
  m.at<float>(3, 4) = std::numeric_limits<float>::quiet_NaN();
  m.at<float>(6, 7) = 1.234f;
  m.at<float>(8, 9) = 0.0f;
  m.at<float>(9, 9) = std::numeric_limits<float>::infinity();
  const RgbdFrame a(colour(), mm, kK), b(colour(), m, kK);
  EXPECT_TRUE(std::isnan(a.depth().at<float>(3, 4)));
  EXPECT_TRUE(std::isnan(b.depth().at<float>(3, 4)));
  EXPECT_TRUE(std::isnan(b.depth().at<float>(8, 9)));
  EXPECT_TRUE(std::isnan(b.depth().at<float>(9, 9)));
  EXPECT_NEAR(a.depth().at<float>(6, 7), 1.234f, 1e-6);
  EXPECT_NEAR(b.depth().at<float>(6, 7), 1.234f, 1e-6);
}

TEST(FrameInput, RejectsEmptyImages) {
  expectInputError([] { RgbdFrame(cv::Mat(), depthMm(), kK); }, "colour image is empty");
  expectInputError([] { RgbdFrame(colour(), cv::Mat(), kK); }, "depth image is empty");
}

TEST(FrameInput, RejectsSizeMismatch) {
  expectInputError([] { RgbdFrame(colour(), cv::Mat(24, 32, CV_16UC1, cv::Scalar(1000)), kK); }, "differ in size");
}

TEST(FrameInput, RejectsWrongTypes) {
  expectInputError([] { RgbdFrame(cv::Mat(48, 64, CV_16UC3), depthMm(), kK); }, "8-bit with 1, 3 or 4 channels");
  expectInputError([] { RgbdFrame(cv::Mat(48, 64, CV_8UC2), depthMm(), kK); }, "8-bit with 1, 3 or 4 channels");
  expectInputError([] { RgbdFrame(colour(), cv::Mat(48, 64, CV_8UC1, cv::Scalar(1)), kK); }, "CV_16UC1");
  expectInputError([] { RgbdFrame(colour(), cv::Mat(48, 64, CV_64FC1, cv::Scalar(1)), kK); }, "CV_32FC1");
}

TEST(FrameInput, RejectsDepthWithoutAnyMeasurement) {
  expectInputError([] { RgbdFrame(colour(), cv::Mat(48, 64, CV_16UC1, cv::Scalar(0)), kK); }, "no valid pixel");
  expectInputError(
      [] { RgbdFrame(colour(), cv::Mat(48, 64, CV_32FC1, cv::Scalar(std::numeric_limits<float>::quiet_NaN())), kK); },
      "no valid pixel");
}

TEST(FrameInput, RejectsBadIntrinsics) {
  expectInputError([] { RgbdFrame(colour(), depthMm(), Intrinsics(0, 500, 32, 24)); }, "focal lengths");
  expectInputError([] { RgbdFrame(colour(), depthMm(), Intrinsics(500, -1, 32, 24)); }, "focal lengths");
  expectInputError([] { RgbdFrame(colour(), depthMm(), Intrinsics(500, std::nan(""), 32, 24)); }, "focal lengths");
  expectInputError([] { RgbdFrame(colour(), depthMm(), Intrinsics(500, 500, std::nan(""), 24)); }, "principal point");
  expectInputError([] { RgbdFrame(colour(), depthMm(), Intrinsics(500, 500, 320, 240)); }, "outside the 64x48 image");
}

TEST(FrameInput, RejectsTheGeometryOfAnotherFrame) {
  const RgbdFrame frame(colour(), depthMm(), kK);
  const RgbdFrame larger(cv::Mat(60, 80, CV_8UC3, cv::Scalar::all(50)), cv::Mat(60, 80, CV_16UC1, cv::Scalar(900)),
                         Intrinsics(500, 510, 40, 30));
  const FrameGeometry other = computeGeometry(larger, GeometryParams());
  FrameGeometry incomplete = computeGeometry(frame, GeometryParams());
  incomplete.x_factor.clear();
  std::vector<cv::KeyPoint> keypoints = {cv::KeyPoint(30.0f, 20.0f, 7.0f)};
  cv::Mat descriptors;
  for (const FrameGeometry* geometry : {&other, static_cast<const FrameGeometry*>(&incomplete)}) {
    expectInputError([&] { Detector().detect(frame, *geometry, keypoints); }, "geometry does not belong");
    expectInputError([&] { Descriptor().compute(frame, *geometry, keypoints, descriptors); }, "does not belong");
  }
  expectInputError([&] { Detector().detect(frame, FrameGeometry(), keypoints); }, "geometry does not belong");
}

TEST(FrameInput, IntrinsicsFromMatrixNeedsAPinholeK) {
  const Intrinsics K = Intrinsics::fromMatrix(cv::Matx33d(585.67, 0, 382.76, 0, 606.56, 223.09, 0, 0, 1));
  EXPECT_DOUBLE_EQ(K.fx, 585.67);
  EXPECT_DOUBLE_EQ(K.fy, 606.56);
  EXPECT_DOUBLE_EQ(K.cx, 382.76);
  EXPECT_DOUBLE_EQ(K.cy, 223.09);
  expectInputError([] { Intrinsics::fromMatrix(cv::Matx33d(500, 1, 320, 0, 500, 240, 0, 0, 1)); }, "not a pinhole");
  expectInputError([] { Intrinsics::fromMatrix(cv::Matx33d(500, 0, 320, 0, 500, 240, 0, 0, 2)); }, "not a pinhole");
}

TEST(Params, ValidationNamesTheField) {
  RisasParams params;
  params.detector.tau = 1.5;
  try {
    params.validate();
    FAIL() << "tau = 1.5 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("detector.tau"), std::string::npos) << e.what();
  }
  params = RisasParams();
  params.descriptor.n_pie = 0;
  EXPECT_THROW(params.validate(), std::invalid_argument);
  params = RisasParams();
  params.descriptor.min_radius_px = 80.0;
  EXPECT_THROW(params.validate(), std::invalid_argument);
  EXPECT_NO_THROW(RisasParams().validate());
}

}  // namespace
}  // namespace risas

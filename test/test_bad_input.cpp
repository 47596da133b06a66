// Issue 20's defects, each as found: what once crashed, read out of bounds,
// was accepted as garbage or was reported wrongly now gives one clear
// InputError (or works). Run under ASan+UBSan by scripts/test.sh.
#include "input_error.hpp"

#include "risas/errors.hpp"
#include "risas/io.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"
#include "risas/risas.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>

namespace risas {
namespace {

using test::inputErrorOf;

#define EXPECT_INPUT_ERROR(call, fragment)                                         \
  do {                                                                             \
    const std::string what = inputErrorOf([&] { call; });                          \
    EXPECT_NE(what.find(fragment), std::string::npos) << what;                     \
    EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;     \
  } while (0)

TEST(BadInput, FramesOfOneRowOrColumnAreRefusedAndTwoByTwoIsDescribedSafely) {
  // placeSamples clamped the bilinear cell to rows - 2 = -1 on a 1-row frame.
  for (const cv::Size size : {cv::Size(1, 30), cv::Size(30, 1), cv::Size(1, 1)}) {
    EXPECT_INPUT_ERROR(RgbdFrame(cv::Mat(size, CV_8UC1, cv::Scalar(9)), cv::Mat(size, CV_16UC1, cv::Scalar(800)),
                                 Intrinsics(30, 30, 0.5, 0.5)),
                       "too small");
  }
  const RgbdFrame tiny(cv::Mat(2, 2, CV_8UC1, cv::Scalar(9)), cv::Mat(2, 2, CV_16UC1, cv::Scalar(800)),
                       Intrinsics(3, 3, 1, 1));
  std::vector<cv::KeyPoint> keypoints = {cv::KeyPoint(0.0f, 0.0f, 4.0f), cv::KeyPoint(1.0f, 1.0f, 4.0f)};
  cv::Mat descriptors;
  Risas::create()->compute(tiny, keypoints, descriptors);
  EXPECT_EQ(descriptors.rows, static_cast<int>(keypoints.size()));
}

TEST(BadInput, AbsurdIntrinsicsAndDepthAreRefused) {
  const cv::Mat grey(48, 64, CV_8UC1, cv::Scalar(50)), depth_mm(48, 64, CV_16UC1, cv::Scalar(1000));
  EXPECT_INPUT_ERROR(RgbdFrame(grey, depth_mm, Intrinsics(1e9, 1e9, 32, 24)), "focal lengths");
  EXPECT_INPUT_ERROR(RgbdFrame(grey, depth_mm, Intrinsics(1e300, 1e300, 32, 24)), "focal lengths");
  EXPECT_INPUT_ERROR(RgbdFrame(grey, depth_mm, Intrinsics(1e-300, 1e-300, 32, 24)), "focal lengths");
  // 64 px wide at fx = 5000: a 0.7 degree view, no RGB-D camera.
  EXPECT_INPUT_ERROR(RgbdFrame(grey, depth_mm, Intrinsics(5000, 5000, 32, 24)), "not those of a camera with a 64x48");
  EXPECT_NO_THROW(RgbdFrame(grey, depth_mm, Intrinsics(60, 60, 32, 24)));
  EXPECT_INPUT_ERROR(Intrinsics::fromMatrix(cv::Matx33d(500, 3, 320, 0, 500, 240, 0, 0, 1)), "not a pinhole");
  // 1e30 m is no measurement: nothing valid is left.
  EXPECT_INPUT_ERROR(RgbdFrame(grey, cv::Mat(48, 64, CV_32FC1, cv::Scalar(1e30f)), Intrinsics(60, 60, 32, 24)),
                     "no valid pixel");
  cv::Mat mixed(48, 64, CV_32FC1, cv::Scalar(1e30f));
  mixed(cv::Rect(0, 0, 10, 10)).setTo(1.5f);
  const RgbdFrame frame(grey, mixed, Intrinsics(60, 60, 32, 24));
  EXPECT_FLOAT_EQ(frame.depth().at<float>(5, 5), 1.5f);
  EXPECT_TRUE(std::isnan(frame.depth().at<float>(20, 20)));
}

class BadFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("risas_bad_input_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
    cv::imwrite(path("rgb.png"), cv::Mat(48, 64, CV_8UC3, cv::Scalar(10, 80, 200)));
    cv::imwrite(path("depth.png"), cv::Mat(48, 64, CV_16UC1, cv::Scalar(1000)));
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::string& text) const { std::ofstream(path(name)) << text; }
  std::filesystem::path dir_;
};

TEST_F(BadFiles, DepthImagesOfTheWrongKindAreNamedAsTheyAre) {
  cv::imwrite(path("rgb16.png"), cv::Mat(48, 64, CV_16UC3, cv::Scalar(1000, 2000, 3000)));
  EXPECT_INPUT_ERROR(readRgbdImages(path("rgb.png"), path("rgb16.png")), "got 16-bit, 3 channels");
  EXPECT_INPUT_ERROR(readRgbdImages(path("rgb.png"), path("rgb.png")), "got 8-bit, 3 channels");
  EXPECT_NO_THROW(readRgbdImages(path("rgb.png"), path("depth.png")));
}

TEST_F(BadFiles, CorruptAndMissingImagesGiveOneLine) {
  write("garbage.png", std::string("\x89PNG\r\n\x1a\n", 8) + "not a png at all");
  std::ifstream good(path("rgb.png"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(good)), std::istreambuf_iterator<char>());
  write("truncated.png", bytes.substr(0, bytes.size() / 2));
  EXPECT_INPUT_ERROR(readRgbdImages(path("garbage.png"), path("depth.png")), "cannot read colour image");
  EXPECT_INPUT_ERROR(readRgbdImages(path("truncated.png"), path("depth.png")), "cannot read colour image");
  EXPECT_INPUT_ERROR(readRgbdImages(path("rgb.png"), path("missing.png")), "no such file");
}

TEST_F(BadFiles, JpegsCutShortOrCorruptAreRefusedNotFilledWithGrey) {
  // OpenCV returns such an image whole, grey where libjpeg's data ran out;
  // only libjpeg's warning tells.
  cv::Mat noise(48, 64, CV_8UC3);
  cv::RNG(7).fill(noise, cv::RNG::UNIFORM, 0, 256);  // scan data the most of the file
  ASSERT_TRUE(cv::imwrite(path("rgb.jpg"), noise));
  std::ifstream good(path("rgb.jpg"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(good)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.substr(bytes.size() - 2), "\xff\xd9");  // the end marker
  const std::string body = bytes.substr(0, bytes.size() - 2);
  const auto read = [&](const std::string& name, const std::string& content) {
    std::ofstream(path(name), std::ios::binary) << content;
    return readRgbdImages(path(name), path("depth.png")).bgr;
  };
  EXPECT_INPUT_ERROR(read("cut.jpg", bytes.substr(0, bytes.size() / 2)),
                     "cut.jpg: Premature end of JPEG file (part of the image is missing)");
  EXPECT_INPUT_ERROR(read("no_end.jpg", body), "Premature end of JPEG file");
  EXPECT_INPUT_ERROR(read("ends_early.jpg", bytes.substr(0, bytes.size() / 2) + "\xff\xd9"),
                     "Corrupt JPEG data: premature end of data segment");
  // Bytes before the end marker lose nothing: the same image.
  const cv::Mat padded = read("padded.jpg", body + std::string(3, '\0') + "\xff\xd9");
  EXPECT_EQ(cv::norm(padded, read("whole.jpg", bytes), cv::NORM_INF), 0.0);
  EXPECT_EQ(padded.size(), noise.size());
}

TEST_F(BadFiles, ParameterFilesWithTyposFractionsAndHugeValuesAreRefused) {
  const auto load = [&](const std::string& text) {
    write("p.yml", "%YAML:1.0\n" + text);
    return RisasParams::load(path("p.yml"));
  };
  EXPECT_INPUT_ERROR(load("detector:\n  tua: 0.5\n"), "unknown parameter 'detector.tua'");
  EXPECT_INPUT_ERROR(load("detectr:\n  tau: 0.5\n"), "unknown parameter section 'detectr'");
  EXPECT_INPUT_ERROR(load("detector:\n  max_keypoints: 2.7\n"), "detector.max_keypoints = 2.7 is not a whole number");
  EXPECT_INPUT_ERROR(load("detector:\n  max_keypoints: 1e20\n"), "detector.max_keypoints = 1e+20 is outside");
  EXPECT_INPUT_ERROR(load("descriptor:\n  shape_orientation: 2\n"), "a flag");
  EXPECT_INPUT_ERROR(load("detector: 3\n"), "section detector is not a map");
  EXPECT_EQ(load("detector:\n  tau: 0.5\n").detector.tau, 0.5);
  // Text that is no YAML at all: the parser's reason with the line, in one line.
  write("broken.yml", "%YAML:1.0\ndetector:\n  tau: [0.5\n");
  try {
    RisasParams::load(path("broken.yml"));
    ADD_FAILURE() << "broken YAML accepted";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("broken.yml(3): "), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.find("OpenCV("), std::string::npos) << what;
  }
  // A root that is not a map, from text (cv::FileStorage::MEMORY).
  cv::FileStorage fs("%YAML:1.0\n---\n[1, 2, 3]\n", cv::FileStorage::READ | cv::FileStorage::MEMORY);
  RisasParams params;
  EXPECT_INPUT_ERROR(params.read(fs.root()), "map of sections");
}

TEST(BadInput, DescriptorSizeIsBounded) {
  DescriptorParams params;
  params.n_pie = 64, params.n_bin = 256, params.n_vec = 64;  // each in range: 1,064,960 dimensions
  EXPECT_INPUT_ERROR(params.validate(), "exceeds 2048");
  params.n_ring = 1, params.n_pie = 8, params.n_bin = 32, params.n_vec = 7;  // 2048
  EXPECT_NO_THROW(params.validate());
  params.shape_weight = 1.0;  // 8 x (32 + 8): the shape labels' own histogram is smaller
  EXPECT_EQ(params.dimension(), 320);
  EXPECT_NO_THROW(params.validate());
  params.n_pie = 64, params.n_bin = 256;  // 64 x (256 + 8)
  EXPECT_INPUT_ERROR(params.validate(), "n_ring * n_pie * (n_bin + n_vec + 1) = 16896 exceeds 2048");
}

TEST(BadInput, ShapeWeightNeedsShapeLabels) {
  DescriptorParams params;  // n_vec 0
  params.shape_weight = 0.5;
  EXPECT_INPUT_ERROR(params.validate(), "shape_weight > 0 needs descriptor.n_vec >= 1");
  params.n_vec = 1;
  EXPECT_NO_THROW(params.validate());
  params.shape_weight = -0.5;
  EXPECT_INPUT_ERROR(params.validate(), "shape_weight");
}

}  // namespace
}  // namespace risas

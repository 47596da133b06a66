// The command-line tools end to end, as a user runs them, on a synthetic
// sequence that risas_render_synthetic writes in the dataset's layout.
#include "risas/io.hpp"

#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include <algorithm>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

namespace risas {
namespace {

namespace fs = std::filesystem;

struct ToolRun {
  int exit_code;
  std::string output;
};

ToolRun run(const std::string& command_line) {
  const fs::path log = fs::temp_directory_path() / ("risas_tool_" + std::to_string(::getpid()) + ".log");
  const int status = std::system((std::string(RISAS_BIN_DIR) + "/" + command_line + " > " + log.string() + " 2>&1").c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  fs::remove(log);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

class Tools : public ::testing::Test {
 protected:
  static fs::path dir;
  static void SetUpTestSuite() {
    dir = fs::temp_directory_path() / ("risas_tools_" + std::to_string(::getpid()));
    const ToolRun r = run("risas_render_synthetic --out " + dir.string() + " --frames 2 --step-deg 6");
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static void TearDownTestSuite() { fs::remove_all(dir); }
  static std::string file(const std::string& name) { return (dir / name).string(); }
  static std::string frameArgs(const std::string& suffix, int k) {
    return " --rgb" + suffix + " " + file("rgb_" + std::to_string(k) + ".png") + " --depth" + suffix + " " +
           file("depth_" + std::to_string(k) + ".png");
  }
};
fs::path Tools::dir;

TEST_F(Tools, ExtractWritesAFeaturesFile) {
  const ToolRun r = run("risas_extract" + frameArgs("", 1) + " --intrinsics " + file("camera-intrinsics.txt") +
                    " --out " + file("f.yml"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("64-d descriptors"), std::string::npos) << r.output;
  const Features f = readFeatures(file("f.yml"));
  EXPECT_GT(f.keypoints.size(), 100u);
  EXPECT_EQ(f.descriptors.cols, 64);  // 8 sectors x 8 rank groups, no shape labels
  EXPECT_EQ(f.geometry.size(), f.keypoints.size());
}

TEST_F(Tools, ExtractTakesIntrinsicsAsNumbersAndAParameterFile) {
  std::ofstream(file("p.yml")) << "%YAML:1.0\ndescriptor:\n  n_pie: 4\n  n_vec: 1\n";
  const ToolRun r = run("risas_extract" + frameArgs("", 1) + " --fx 570 --fy 570 --cx 319.5 --cy 239.5 --params " +
                    file("p.yml") + " --out " + file("g.yml"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(readFeatures(file("g.yml")).descriptors.cols, 4 * 8 * 2);
}

TEST_F(Tools, ExtractReadsTumDepthUnits) {
  cv::Mat depth_tum;
  cv::imread(file("depth_1.png"), cv::IMREAD_UNCHANGED).convertTo(depth_tum, CV_16U, 5.0);  // 5000 a metre
  cv::imwrite(file("depth_1_tum.png"), depth_tum);
  const std::string common = " --rgb " + file("rgb_1.png") + " --intrinsics " + file("camera-intrinsics.txt");
  ToolRun r = run("risas_extract" + common + " --depth " + file("depth_1.png") + " --out " + file("mm.yml"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run("risas_extract" + common + " --depth " + file("depth_1_tum.png") + " --depth-units 5000 --out " +
          file("tum.yml"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Features mm = readFeatures(file("mm.yml")), tum = readFeatures(file("tum.yml"));
  ASSERT_EQ(mm.keypoints.size(), tum.keypoints.size());
  for (size_t i = 0; i < mm.keypoints.size(); ++i) {
    EXPECT_EQ(mm.keypoints[i].pt, tum.keypoints[i].pt);
    EXPECT_NEAR(cv::norm(mm.geometry[i].point - tum.geometry[i].point), 0.0, 1e-5);
  }
  r = run("risas_extract" + common + " --depth " + file("depth_1_tum.png") + " --depth-units 0 --out " +
          file("bad.yml"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("depth units per metre must be positive"), std::string::npos) << r.output;
}

TEST_F(Tools, MatchFindsTheKnownMotionAndDrawsTheOverlay) {
  const ToolRun r = run("risas_match" + frameArgs("1", 1) + frameArgs("2", 2) + " --intrinsics " +
                    file("camera-intrinsics.txt") + " --overlay " + file("overlay.png") + " --gt-rotation " +
                    file("R1-2.txt") + " --gt-translation " + file("T1-2.txt"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("summary:"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(file("overlay.png")));
  // The motion error line: rotation error below a degree, translation below 2 cm.
  const size_t at = r.output.find("motion error: rotation ");
  ASSERT_NE(at, std::string::npos) << r.output;
  double rotation_error = 0.0;
  std::istringstream(r.output.substr(at + 23)) >> rotation_error;
  EXPECT_LT(rotation_error, 1.0) << r.output;
  const size_t t_at = r.output.find("(|t| ", at);
  double translation_error = 1.0;
  std::istringstream(r.output.substr(t_at + 5)) >> translation_error;
  EXPECT_LT(translation_error, 0.02) << r.output;
}

TEST_F(Tools, WrongUsageAndBadInputFailClearly) {
  ToolRun r = run("risas_extract --rgb x.png");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--help"), std::string::npos) << r.output;
  r = run("risas_extract --bogus 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown option --bogus"), std::string::npos) << r.output;
  r = run("risas_extract --rgb " + file("missing.png") + " --depth " + file("depth_1.png") + " --intrinsics " +
          file("camera-intrinsics.txt") + " --out " + file("h.yml"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("cannot read colour image"), std::string::npos) << r.output;
  r = run("risas_extract" + frameArgs("", 1) + " --fx 0 --fy 570 --cx 319.5 --cy 239.5 --out " + file("h.yml"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("focal lengths"), std::string::npos) << r.output;
  // An unwritable output is found before the extraction (issue 20), in one line.
  r = run("risas_extract" + frameArgs("", 1) + " --intrinsics " + file("camera-intrinsics.txt") +
          " --out /nonexistent-folder/h.yml");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("cannot write /nonexistent-folder/h.yml: no folder"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("keypoints"), std::string::npos) << "extracted first: " << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  r = run("risas_match --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("--overlay"), std::string::npos);
}

}  // namespace
}  // namespace risas

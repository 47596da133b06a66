// The command-line tools end to end, as a user runs them, on a synthetic
// sequence that risas_render_synthetic writes in the dataset's layout.
#include "tool_run.hpp"

#include "risas/io.hpp"
#include "risas/tum_sequence.hpp"

#include <Eigen/Geometry>

#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace risas {
namespace {

namespace fs = std::filesystem;

using test::ToolRun;

ToolRun run(const std::string& command_line) { return test::runTool(command_line); }

class Tools : public ::testing::Test {
 protected:
  static fs::path dir;
  static void SetUpTestSuite() {
    dir = fs::temp_directory_path() / ("risas_tools_" + std::to_string(::getpid()));
    const ToolRun r = run("risas_render_synthetic --out " + dir.string() + " --frames 3 --step-deg 6");
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static void TearDownTestSuite() { fs::remove_all(dir); }
  static std::string file(const std::string& name) { return (dir / name).string(); }
  static std::string frameArgs(const std::string& suffix, int k) {
    return " --rgb" + suffix + " " + file("rgb_" + std::to_string(k) + ".png") + " --depth" + suffix + " " +
           file("depth_" + std::to_string(k) + ".png");
  }
  // The first `frames` rendered frames as a TUM RGB-D folder: depth in 5000
  // units a metre, and groundtruth.txt with frame 1 as the world.
  static fs::path tumFolder(int frames) {
    std::vector<int> rendered;
    for (int k = 1; k <= frames; ++k) rendered.push_back(k);
    return tumFolder("tum" + std::to_string(frames), rendered);
  }
  // The rendered frames `rendered` (1-based, in that order, a frame again
  // where the camera comes back) as the TUM folder `name`, stamped 1, 2, ...
  static fs::path tumFolder(const std::string& name, const std::vector<int>& rendered) {
    const fs::path tum = dir / name;
    fs::create_directories(tum / "rgb");
    fs::create_directories(tum / "depth");
    std::ofstream rgb_list(tum / "rgb.txt"), depth_list(tum / "depth.txt"), truth(tum / "groundtruth.txt");
    for (size_t i = 0; i < rendered.size(); ++i) {
      const std::string k = std::to_string(rendered[i]), stamp = std::to_string(i + 1);
      const std::string image = stamp + ".png";
      fs::copy_file(file("rgb_" + k + ".png"), tum / "rgb" / image, fs::copy_options::overwrite_existing);
      cv::Mat depth;
      cv::imread(file("depth_" + k + ".png"), cv::IMREAD_UNCHANGED).convertTo(depth, CV_16U, 5.0);
      cv::imwrite((tum / "depth" / image).string(), depth);
      rgb_list << stamp << ".0 rgb/" << image << "\n";
      depth_list << stamp << ".001 depth/" << image << "\n";
      const Eigen::Isometry3d pose = readPoseFiles(file("R1-" + k + ".txt"), file("T1-" + k + ".txt"));
      const Eigen::Vector3d t = pose.translation();
      const Eigen::Quaterniond q(pose.linear());
      truth << stamp << ".0 " << t.x() << " " << t.y() << " " << t.z() << " " << q.x() << " " << q.y() << " "
            << q.z() << " " << q.w() << "\n";
    }
    return tum;
  }
  // A copy of the folder `tum` as `name` whose groundtruth.txt's clock runs
  // `seconds` late: each pose stamped that much after its frame.
  static fs::path lateTruth(const fs::path& tum, const std::string& name, double seconds) {
    const fs::path late = dir / name;
    fs::remove_all(late);
    fs::copy(tum, late, fs::copy_options::recursive);
    std::ifstream in(tum / "groundtruth.txt");
    std::ofstream out(late / "groundtruth.txt");
    std::string stamp, pose;
    while (in >> stamp && std::getline(in, pose)) out << std::stod(stamp) + seconds << pose << "\n";
    return late;
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
  EXPECT_EQ(f.descriptors.cols, 64);  // 2 rings x 8 sectors x 4 rank groups, no shape labels
  EXPECT_EQ(f.descriptor_layout, "n_ring=2 n_pie=8 n_bin=4 n_vec=0");
  EXPECT_EQ(f.geometry.size(), f.keypoints.size());
}

TEST_F(Tools, ExtractTakesIntrinsicsAsNumbersAndAParameterFile) {
  std::ofstream(file("p.yml")) << "%YAML:1.0\ndescriptor:\n  n_pie: 4\n  n_vec: 1\n";
  const ToolRun r = run("risas_extract" + frameArgs("", 1) + " --fx 570 --fy 570 --cx 319.5 --cy 239.5 --params " +
                    file("p.yml") + " --out " + file("g.yml"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(readFeatures(file("g.yml")).descriptors.cols, 4 * 8 * 2);
  EXPECT_EQ(readFeatures(file("g.yml")).descriptor_layout, "n_ring=2 n_pie=4 n_bin=4 n_vec=1");
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
  for (const char* units : {"0", "-5", "0.5", "1e9"}) {
    r = run("risas_extract" + common + " --depth " + file("depth_1_tum.png") + " --depth-units " + units +
            " --out " + file("bad.yml"));
    EXPECT_EQ(r.exit_code, 1) << units;
    EXPECT_NE(r.output.find("depth units per metre must be within [1, 100000] (1000: millimetres; TUM RGB-D: "
                            "5000), got "),
              std::string::npos)
        << r.output;
  }
}

// The last number on the benchmark's line that starts with `stage`.
double benchmarkColumn(const std::string& output, const std::string& stage) {
  const size_t at = output.find("\n" + stage);
  if (at == std::string::npos) return -1.0;
  const std::string line = output.substr(at + 1, output.find('\n', at + 1) - at - 1);
  return std::stod(line.substr(line.find_last_of(' ') + 1));
}

TEST_F(Tools, BenchmarkTimesTheSameFramesFromEitherLayout) {
  const fs::path tum = tumFolder(2);
  const ToolRun from_data = run("risas_benchmark --data " + dir.string() + " --frames 2 --repeats 1");
  ASSERT_EQ(from_data.exit_code, 0) << from_data.output;
  const ToolRun from_tum = run("risas_benchmark --tum " + tum.string() + " --intrinsics " +
                               file("camera-intrinsics.txt") + " --frames 2 --repeats 1");
  ASSERT_EQ(from_tum.exit_code, 0) << from_tum.output;
  EXPECT_NE(from_tum.output.find("2 frame(s) 640x480 from " + tum.string()), std::string::npos) << from_tum.output;
  // The same frames and depth: the same keypoints, ORB's too.
  const double keypoints = benchmarkColumn(from_data.output, "RISAS total");
  EXPECT_GT(keypoints, 50.0) << from_data.output;
  EXPECT_EQ(benchmarkColumn(from_tum.output, "RISAS total"), keypoints) << from_tum.output;
  EXPECT_EQ(benchmarkColumn(from_tum.output, "OpenCV ORB"), benchmarkColumn(from_data.output, "OpenCV ORB"));
  // Without intrinsics, or with both sources, a one-line usage error.
  ToolRun r = run("risas_benchmark --tum " + tum.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run("risas_benchmark --tum " + tum.string() + " --data " + dir.string() + " --fx 500 --fy 500 --cx 320 --cy 240");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("not both"), std::string::npos) << r.output;
}

// The odometry tool tracks the same features once per RANSAC seed: the
// trajectory and the first ATE are the first seed's, as a run without the
// option gives them, and the spread over the seeds follows.
TEST_F(Tools, OdometryRunsEachRansacSeedAndWritesTheFirstSeedsTrajectory) {
  const std::string tum = tumFolder(3).string();
  const std::string common = "risas_odometry --tum " + tum + " --intrinsics " + file("camera-intrinsics.txt");
  const ToolRun one = run(common + " --out " + file("one.txt") + " --frames " + file("one.csv"));
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_NE(one.output.find("3 frames, 0 not tracked"), std::string::npos) << one.output;
  // The rendered motion is exact: the covariance (its 1 mm floor) covers the
  // drift with room to spare.
  const size_t consistency = one.output.find("Covariance against the drift from the first tracked pose (2 poses");
  ASSERT_NE(consistency, std::string::npos) << one.output;
  const size_t ratio = one.output.find("mean sigma^2 ", consistency);
  ASSERT_NE(ratio, std::string::npos) << one.output;
  EXPECT_LT(std::stod(one.output.substr(ratio + 13)), 1.0) << one.output;
  // The same for the motions from frame to frame (the twist's), two of them.
  const size_t motion = one.output.find("Frame-to-frame motion's covariance (the twist's) against the truth's motion (2 motions)");
  ASSERT_NE(motion, std::string::npos) << one.output;
  const size_t motion_ratio = one.output.find("mean sigma^2 ", motion);
  ASSERT_NE(motion_ratio, std::string::npos) << one.output;
  EXPECT_LT(std::stod(one.output.substr(motion_ratio + 13)), 1.0) << one.output;
  // Per frame, the pose's standard deviations: none at the first (the world
  // is its camera), some at every tracked one.
  std::ifstream csv(file("one.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line, "stamp,tracked,keyframe,features,matches,inliers,rmse,position_sd,rotation_sd_deg");
  std::vector<double> position_sd;
  while (std::getline(csv, line)) {
    const size_t last = line.rfind(','), before = line.rfind(',', last - 1);
    position_sd.push_back(std::stod(line.substr(before + 1, last - before - 1)));
  }
  ASSERT_EQ(position_sd.size(), 3u);
  EXPECT_EQ(position_sd[0], 0.0);
  EXPECT_GT(position_sd[1], 0.0);
  EXPECT_GT(position_sd[2], 0.0);
  EXPECT_EQ(one.output.find("RANSAC seeds"), std::string::npos) << one.output;
  const ToolRun three = run(common + " --out " + file("three.txt") + " --ransac-seeds 3");
  ASSERT_EQ(three.exit_code, 0) << three.output;
  const auto ateLine = [](const std::string& output) { return output.substr(output.find("ATE RMSE "), 40); };
  EXPECT_EQ(ateLine(three.output), ateLine(one.output));
  EXPECT_EQ(test::fileText(file("three.txt")), test::fileText(file("one.txt")));
  // The rendered motion is exact: every seed recovers it within a centimetre.
  const size_t over = three.output.find("ATE RMSE over 3 RANSAC seeds: mean ");
  ASSERT_NE(over, std::string::npos) << three.output;
  const size_t highest = three.output.find(" to ", over);
  ASSERT_NE(highest, std::string::npos) << three.output;
  EXPECT_LT(std::stod(three.output.substr(highest + 4)), 0.01) << three.output;
  const size_t median = three.output.find(" m, median ", over);  // beside the mean, within the range
  const size_t lowest = three.output.find(" m, from ", over);
  ASSERT_TRUE(median != std::string::npos && lowest != std::string::npos && median < lowest) << three.output;
  const double middle = std::stod(three.output.substr(median + 11));
  EXPECT_LE(std::stod(three.output.substr(lowest + 9)), middle) << three.output;
  EXPECT_LE(middle, std::stod(three.output.substr(highest + 4))) << three.output;
  const ToolRun none = run(common + " --out " + file("none.txt") + " --ransac-seeds 0");
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_NE(none.output.find("--ransac-seeds must be a whole number in [1, 1000], got '0'"), std::string::npos)
      << none.output;
  // A count beyond reason is refused before the work (1e9 seeds would run for
  // days), and one beyond an int before it is cast (1e20).
  for (const char* count : {"1e9", "1e20", "2.5"}) {
    const ToolRun absurd = run(common + " --out " + file("none.txt") + " --ransac-seeds " + count);
    EXPECT_EQ(absurd.exit_code, 2) << absurd.output;
    EXPECT_NE(absurd.output.find("--ransac-seeds must be a whole number in [1, 1000]"), std::string::npos)
        << absurd.output;
  }
  const ToolRun no_frames = run(common + " --out " + file("none.txt") + " --max-frames 0");
  EXPECT_EQ(no_frames.exit_code, 2) << no_frames.output;
}

// The first number after `label` in `output`, -1 when it is not there.
double numberAfter(const std::string& output, const std::string& label) {
  const size_t at = output.find(label);
  return at == std::string::npos ? -1.0 : std::stod(output.substr(at + label.size()));
}

// --image-noise: each colour image gets its noise before its features, the
// same draw for the same --noise-seed (the same trajectory, to the digit),
// another for another seed; the run says so. Nonsense is one line, before
// the work.
TEST_F(Tools, OdometryAddsTheSameImageNoiseForASeedAndOtherNoiseForAnother) {
  const std::string common =
      "risas_odometry --tum " + tumFolder(3).string() + " --intrinsics " + file("camera-intrinsics.txt");
  const auto trajectory = [&](const std::string& name) { return test::fileText(file(name)); };
  ToolRun r = run(common + " --out " + file("clean.txt"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("grey noise"), std::string::npos) << r.output;
  for (const std::string name : {"noisy_a.txt", "noisy_b.txt"}) {
    r = run(common + " --image-noise 5 --noise-seed 1 --out " + file(name));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Colour images with grey noise of sigma 5 (noise seed 1) before their features"),
              std::string::npos)
        << r.output;
    // The rendered motion is exact, and noise of 5 grey levels does not lose it.
    EXPECT_NE(r.output.find("3 frames, 0 not tracked"), std::string::npos) << r.output;
    EXPECT_LT(numberAfter(r.output, "ATE RMSE "), 0.01) << r.output;
  }
  EXPECT_EQ(trajectory("noisy_b.txt"), trajectory("noisy_a.txt"));
  EXPECT_NE(trajectory("noisy_a.txt"), trajectory("clean.txt"));
  r = run(common + " --image-noise 5 --noise-seed 2 --out " + file("noisy_c.txt"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(trajectory("noisy_c.txt"), trajectory("noisy_a.txt"));
  const std::map<std::string, std::string> refused = {
      {" --image-noise -1", "risas_odometry: --image-noise is 0 to 255 grey levels, not -1"},
      {" --image-noise 300", "risas_odometry: --image-noise is 0 to 255 grey levels, not 300"},
      {" --image-noise nan", "risas_odometry: --image-noise expects a number, got 'nan'"},
      {" --noise-seed 3", "risas_odometry: --noise-seed does not apply without --image-noise"},
      {" --image-noise 2 --noise-seed -3", "risas_odometry: --noise-seed must be a whole number in [0, 1000000000]"},
  };
  for (const auto& [options, expected] : refused) {
    r = run(common + options + " --out " + file("refused.txt"));
    EXPECT_EQ(r.exit_code, 2) << options << ": " << r.output;
    EXPECT_EQ(r.output.rfind(expected, 0), 0u) << options << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << options << ": " << r.output;
  }
}

// --truth-offset shifts groundtruth.txt's stamps before the frames take
// the nearest: a truth whose clock runs a second late pairs each frame with
// the pose a second before, unless the offset takes the second back.
TEST_F(Tools, OdometryPairsTheFramesWithTheTruthShiftedByTheOffset) {
  const std::string common = "risas_odometry --intrinsics " + file("camera-intrinsics.txt") + " --out " + file("o.txt");
  // The camera swings out and back: rendered frames 1 2 3 2 1, stamps 1..5.
  const fs::path swing = tumFolder("swing_truth", {1, 2, 3, 2, 1});
  const fs::path late = lateTruth(swing, "swing_truth_late", 1.0);
  const ToolRun right = run(common + " --tum " + swing.string());
  const ToolRun wrong = run(common + " --tum " + late.string());
  const ToolRun offset = run(common + " --tum " + late.string() + " --truth-offset -1");
  for (const ToolRun* r : {&right, &wrong, &offset}) ASSERT_EQ(r->exit_code, 0) << r->output;
  // Paired a second late, frames 2..5 take the poses of 1..4: centimetres off.
  EXPECT_GT(numberAfter(wrong.output, "ATE RMSE "), 0.01) << wrong.output;
  EXPECT_LT(numberAfter(right.output, "ATE RMSE "), 0.005) << right.output;
  // Taken back, the truth is the right one's: every score the same.
  EXPECT_EQ(offset.output, right.output);
  // Without a truth the offset would be ignored in silence: refused.
  fs::remove(late / "groundtruth.txt");
  const ToolRun none = run(common + " --tum " + late.string() + " --truth-offset -1");
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_NE(none.output.find("--truth-offset does not apply without " + (late / "groundtruth.txt").string()),
            std::string::npos)
      << none.output;
  const ToolRun typo = run(common + " --tum " + swing.string() + " --truth-offset 1s");
  EXPECT_EQ(typo.exit_code, 2) << typo.output;
  EXPECT_NE(typo.output.find("--truth-offset expects a number, got '1s'"), std::string::npos) << typo.output;
}

// The evaluation's pairs on a recording take the same offset: with the
// late truth taken back, pairs.csv is the right truth's but for the scene
// (the folder's name) and the time each frame took.
TEST_F(Tools, EvaluationPairsTheFramesWithTheTruthShiftedByTheOffset) {
  const fs::path swing = tumFolder("swing_evaluated", {1, 2, 3});
  const fs::path late = lateTruth(swing, "swing_evaluated_late", 1.0);
  const std::string common =
      "risas_evaluate --intrinsics " + file("camera-intrinsics.txt") + " --methods RISAS --no-plots";
  // pairs.csv's rows without the scene (the folder's name) and the
  // ms_per_frame column (the 17th).
  const auto rows = [](const std::string& folder) {
    std::ifstream in(fs::path(folder) / "pairs.csv");
    std::vector<std::string> kept;
    for (std::string line; std::getline(in, line);) {
      size_t from = 0;
      for (int comma = 0; comma < 16 && from != std::string::npos; ++comma) from = line.find(',', from + 1);
      const size_t to = from == std::string::npos ? from : line.find(',', from + 1);
      const std::string timeless = to == std::string::npos ? line : line.substr(0, from) + line.substr(to);
      kept.push_back(timeless.substr(timeless.find(',')));
    }
    return kept;
  };
  const ToolRun right = run(common + " --tum " + swing.string() + " --out " + file("eval_right"));
  const ToolRun wrong = run(common + " --tum " + late.string() + " --out " + file("eval_late"));
  const ToolRun offset =
      run(common + " --tum " + late.string() + " --truth-offset -1 --out " + file("eval_offset"));
  for (const ToolRun* r : {&right, &wrong, &offset}) ASSERT_EQ(r->exit_code, 0) << r->output;
  const std::vector<std::string> expected = rows(file("eval_right"));
  ASSERT_EQ(expected.size(), 3u);  // the header and pairs (1, 2), (2, 3)
  EXPECT_EQ(expected[0].find("ms_per_frame"), std::string::npos) << expected[0];
  EXPECT_EQ(rows(file("eval_offset")), expected);
  // A second late, frame 1 has no pose: one pair is left.
  EXPECT_EQ(rows(file("eval_late")).size(), 2u);
  EXPECT_NE(wrong.output.find("1 of 3 frames have no ground-truth pose within 0.02 s: left out"), std::string::npos)
      << wrong.output;
  EXPECT_EQ(offset.output.find("left out"), std::string::npos) << offset.output;
  const ToolRun refused = run(common + " --data " + dir.string() + " --truth-offset 1 --out " + file("eval_data"));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_EQ(refused.output.rfind("risas_evaluate: --truth-offset does not apply with --data", 0), 0u)
      << refused.output;
}

// --start and --step pick the frames a chain tracks, as a folder that keeps
// only those frames would give them; several starts are several chains,
// each as a run from that start alone reports it, and their mean follows.
TEST_F(Tools, OdometryTracksAChainFromEachStartAtItsStep) {
  // The camera swings out and back: rendered frames 1 2 3 2 1, stamps 1..5.
  const std::string common = "risas_odometry --intrinsics " + file("camera-intrinsics.txt");
  const std::string swing = tumFolder("swing", {1, 2, 3, 2, 1}).string();
  // Every second frame: stamps 1, 3 and 5, as the folder that keeps every
  // second line of rgb.txt and depth.txt gives them (docs/odometry.md).
  ToolRun r = run(common + " --tum " + swing + " --step 2 --out " + file("every_2nd.txt"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path thinned = dir / "thinned";
  fs::remove_all(thinned);
  fs::copy(swing, thinned, fs::copy_options::recursive);
  for (const char* list : {"rgb.txt", "depth.txt"}) {
    std::ifstream in(fs::path(swing) / list);
    std::ofstream kept(thinned / list);
    std::string line;
    for (int n = 0; std::getline(in, line); ++n) {
      if (n % 2 == 0) kept << line << "\n";
    }
  }
  const ToolRun by_hand = run(common + " --tum " + thinned.string() + " --out " + file("thinned.txt"));
  ASSERT_EQ(by_hand.exit_code, 0) << by_hand.output;
  EXPECT_EQ(numberAfter(r.output, "ATE RMSE "), numberAfter(by_hand.output, "ATE RMSE ")) << r.output;
  const std::vector<StampedPose> chain = readTumTrajectory(file("every_2nd.txt")),
                                 kept = readTumTrajectory(file("thinned.txt"));
  ASSERT_EQ(chain.size(), 3u);
  ASSERT_EQ(kept.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(chain[i].stamp, 1.0 + 2.0 * i);
    EXPECT_EQ(kept[i].stamp, chain[i].stamp);
    EXPECT_TRUE(chain[i].world_T_camera.isApprox(kept[i].world_T_camera, 1e-9)) << i;
  }
  // Frame 3 is 12 degrees from frame 1, and the chain comes back to frame 1.
  EXPECT_GT(Eigen::AngleAxisd(chain[1].world_T_camera.linear()).angle(), 0.1);
  EXPECT_LT(Eigen::AngleAxisd(chain[2].world_T_camera.linear()).angle(), 0.02);
  // Three chains from frames 0, 1 and 2, every frame: 5, 4 and 3 frames.
  // The last has no texture: lost, held at the fourth's pose 16 cm away,
  // it weighs on each chain's ATE as one pose of 5, 4 and 3.
  const std::string lost = tumFolder("swing_lost", {1, 2, 3, 2, 1}).string();
  cv::imwrite((fs::path(lost) / "rgb" / "5.png").string(), cv::Mat(480, 640, CV_8UC3, cv::Scalar(128, 128, 128)));
  const ToolRun chains = run(common + " --tum " + lost + " --start 0,1,2 --ransac-seeds 2 --out " + file("c.txt") +
                             " --frames " + file("c.csv"));
  ASSERT_EQ(chains.exit_code, 0) << chains.output;
  std::vector<double> chain_means;
  // Each chain's covariance checks (drift, then frame to frame; position,
  // then rotation), as printed with two decimals.
  std::vector<std::array<double, 4>> checks;
  for (int start = 0; start < 3; ++start) {
    const std::string header = "Chain from frame " + std::to_string(start) + ", step 1:\n";
    const size_t at = chains.output.find(header);
    ASSERT_NE(at, std::string::npos) << chains.output;
    // This chain's lines only: up to the next chain's, or the summary.
    std::string report = chains.output.substr(at + header.size());
    report = report.substr(0, std::min(report.find("Chain from frame "), report.find("ATE RMSE over 3 chains")));
    EXPECT_EQ(report.rfind("RISAS odometry: " + std::to_string(5 - start) + " frames, 1 not tracked", 0), 0u)
        << report;
    chain_means.push_back(numberAfter(report, "ATE RMSE over 2 RANSAC seeds: mean "));
    const size_t drift = report.find("Covariance against the drift from the first tracked pose");
    const size_t motion = report.find("Frame-to-frame motion's covariance (the twist's) against");
    ASSERT_TRUE(drift != std::string::npos && motion != std::string::npos) << report;
    checks.push_back({numberAfter(report.substr(drift), "mean sigma^2 "),
                      numberAfter(report.substr(drift), "; rotation "),
                      numberAfter(report.substr(motion), "mean sigma^2 "),
                      numberAfter(report.substr(motion), "; rotation ")});
    for (double ratio : checks.back()) EXPECT_GE(ratio, 0.0) << report;  // -1: not printed
  }
  // The last chain as a run from its start alone reports it.
  const ToolRun alone = run(common + " --tum " + lost + " --start 2 --ransac-seeds 2 --out " + file("alone.txt"));
  ASSERT_EQ(alone.exit_code, 0) << alone.output;
  const std::string last = chains.output.substr(chains.output.find("Chain from frame 2, step 1:\n"));
  EXPECT_EQ(numberAfter(alone.output, "ATE RMSE over 2 RANSAC seeds: mean "), chain_means[2]) << alone.output;
  EXPECT_EQ(numberAfter(last, "ATE RMSE "), numberAfter(alone.output, "ATE RMSE ")) << last << alone.output;
  EXPECT_EQ(numberAfter(last, "RPE (1 frame) translation RMSE "),
            numberAfter(alone.output, "RPE (1 frame) translation RMSE "))
      << last << alone.output;
  // The lost pose weighs more on the shorter chains.
  EXPECT_GT(chain_means[0], 0.01) << chains.output;
  EXPECT_LT(chain_means[0] + 0.005, chain_means[1]) << chains.output;
  EXPECT_LT(chain_means[1] + 0.005, chain_means[2]) << chains.output;
  const std::string over = "ATE RMSE over 3 chains (step 1, from frames 0, 1, 2), each chain's mean over 2 RANSAC "
                           "seeds: mean ";
  EXPECT_NEAR(numberAfter(chains.output, over), (chain_means[0] + chain_means[1] + chain_means[2]) / 3.0, 1e-4)
      << chains.output;
  // The covariance checks over the chains: each ratio's mean and range over
  // the chains' (within two roundings to two decimals: theirs and its own).
  const std::string over_chains = " over 3 chains, each chain's first seed: position mean |e|^2 / mean sigma^2 mean ";
  const std::array<std::string, 2> summaries = {"Covariance against the drift" + over_chains,
                                                "Frame-to-frame motion's covariance (the twist's)" + over_chains};
  for (size_t s = 0; s < summaries.size(); ++s) {
    const size_t at = chains.output.find(summaries[s]);
    ASSERT_NE(at, std::string::npos) << summaries[s] << "\n" << chains.output;
    const std::string summary = chains.output.substr(at + summaries[s].size() - std::string("mean ").size());
    for (size_t k = 0; k < 2; ++k) {
      const std::string rotation = "; rotation ";
      const std::string figure = k == 0 ? summary : summary.substr(summary.find(rotation) + rotation.size());
      std::vector<double> per_chain;
      for (const std::array<double, 4>& c : checks) per_chain.push_back(c[2 * s + k]);
      const auto [lowest, highest] = std::minmax_element(per_chain.begin(), per_chain.end());
      EXPECT_NEAR(numberAfter(figure, "mean "), (per_chain[0] + per_chain[1] + per_chain[2]) / 3.0, 0.0101) << figure;
      EXPECT_NEAR(numberAfter(figure, ", from "), *lowest, 0.0101) << figure;
      EXPECT_NEAR(numberAfter(figure, " to "), *highest, 0.0101) << figure;
    }
  }
  // The trajectory and the frame table written are the first chain's.
  EXPECT_EQ(readTumTrajectory(file("c.txt")).size(), 5u);
  std::ifstream csv(file("c.csv"));
  EXPECT_EQ(std::count(std::istreambuf_iterator<char>(csv), std::istreambuf_iterator<char>(), '\n'), 6);
  // A chain too short to score is said to be, and the mean is over the others.
  r = run(common + " --tum " + swing + " --start 0,1 --step 2 --out " + file("c2.txt"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Not scored: the ATE needs 3 frames with ground truth (within 0.02 s), 2 have it"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("ATE RMSE over 1 of 2 chains (step 2, from frames 0, 1), each chain's mean over 1 RANSAC "
                          "seed: mean "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("Covariance against the drift over 1 of 2 chains, each chain's first seed: "),
            std::string::npos)
      << r.output;
  // A start past the recording, a step of 0 or a start given twice: one line.
  const std::map<std::string, std::pair<int, std::string>> refused = {
      {" --start 0,5", {1, "risas_odometry: error: --start 5 is past " + swing + "'s 5 frames (the first is 0)"}},
      {" --step 0", {2, "risas_odometry: --step must be a whole number in [1, 1000000], got '0'"}},
      {" --start 1,1", {2, "risas_odometry: --start names '1' twice"}},
      {" --start 1,01", {2, "risas_odometry: --start names 1 twice"}},
      {" --start -1", {2, "risas_odometry: --start must be a whole number in [0, 100000000], got '-1'"}},
  };
  for (const auto& [options, expected] : refused) {
    r = run(common + " --tum " + swing + options + " --out " + file("refused.txt"));
    EXPECT_EQ(r.exit_code, expected.first) << options << ": " << r.output;
    EXPECT_EQ(r.output.substr(0, r.output.find('\n')).rfind(expected.second, 0), 0u) << options << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << options << ": " << r.output;
  }
}

// The trajectory is the result: a sequence too short to score (two frames
// with ground truth) still gets it, with a line saying why there is no ATE,
// and an RPE over a gap no two frames span says so rather than printing 0.
TEST_F(Tools, OdometryWritesWhatItCannotScoreAndSaysWhy) {
  const std::string common = "risas_odometry --intrinsics " + file("camera-intrinsics.txt");
  ToolRun r = run(common + " --tum " + tumFolder(2).string() + " --out " + file("two.txt") + " --ransac-seeds 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("trajectory written to " + file("two.txt")), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Not scored: the ATE needs 3 frames with ground truth (within 0.02 s), 2 have it"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("ATE RMSE"), std::string::npos) << r.output;
  EXPECT_EQ(readTumTrajectory(file("two.txt")).size(), 2u);
  r = run(common + " --tum " + tumFolder(3).string() + " --out " + file("gap.txt") + " --delta 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ATE RMSE "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("RPE (3 frame): no two frames with ground truth that far apart"), std::string::npos)
      << r.output;
  // No ground truth at all: said so, and the seeds that would only score it are not run.
  const fs::path untruthful = tumFolder(3);
  fs::remove(untruthful / "groundtruth.txt");
  r = run(common + " --tum " + untruthful.string() + " --out " + file("free.txt") + " --ransac-seeds 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Not scored: " + untruthful.string() +
                          " has no groundtruth.txt; one RANSAC seed run, not 3\n"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("over 3 RANSAC seeds"), std::string::npos) << r.output;
  EXPECT_EQ(readTumTrajectory(file("free.txt")).size(), 3u);
}

// A recording's colour image without a depth image near it is left out with
// a note, not in silence: a depth stream that lags by more than the
// tolerance would lose most frames.
TEST_F(Tools, RecordingsFramesLeftOutAreNoted) {
  const fs::path tum = tumFolder(3);
  std::ofstream(tum / "depth.txt") << "1.001 depth/1.png\n3.001 depth/3.png\n";  // frame 2's depth is gone
  const std::string note = ": " + tum.string() + ": 1 of 3 colour images have no depth image within 0.02 s: left out\n";
  const std::string intrinsics = " --intrinsics " + file("camera-intrinsics.txt");
  for (const std::string tool : {"risas_odometry", "risas_benchmark", "risas_evaluate"}) {
    const std::string options = tool == "risas_odometry"    ? " --out " + file("left_out.txt")
                                : tool == "risas_benchmark" ? " --frames 2 --repeats 1"
                                                            : " --methods ORB --no-plots --out " + file("eval");
    const ToolRun r = run(tool + " --tum " + tum.string() + intrinsics + options);
    EXPECT_EQ(r.exit_code, 0) << tool << ": " << r.output;
    EXPECT_NE(r.output.find(tool + note), std::string::npos) << tool << ": " << r.output;
  }
  EXPECT_EQ(readTumTrajectory(file("left_out.txt")).size(), 2u);
  const ToolRun whole =
      run("risas_odometry --tum " + tumFolder(3).string() + intrinsics + " --out " + file("whole.txt"));
  EXPECT_EQ(whole.output.find("left out"), std::string::npos) << whole.output;
}

// The same odometry on ORB's features, and on ORB's strongest keypoint of
// each image point (ORB-distinct): fewer features a frame, every frame
// tracked on the rendered sequence.
TEST_F(Tools, OdometryRunsOnOrbAndOnOrbDistinct) {
  const std::string tum = tumFolder(3).string();
  const std::string common = "risas_odometry --tum " + tum + " --intrinsics " + file("camera-intrinsics.txt");
  std::map<std::string, std::vector<int>> features;
  for (const std::string name : {"ORB", "ORB-distinct"}) {
    const ToolRun r = run(common + " --features " + name + " --out " + file(name + ".txt") + " --frames " +
                          file(name + ".csv"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("3 frames, 0 not tracked"), std::string::npos) << name << ": " << r.output;
    std::ifstream csv(file(name + ".csv"));
    std::string line;
    ASSERT_TRUE(std::getline(csv, line));
    while (std::getline(csv, line)) {
      std::stringstream fields(line);
      std::string field;
      for (int column = 0; column < 4; ++column) std::getline(fields, field, ',');  // stamp, tracked, keyframe, features
      features[name].push_back(std::stoi(field));
    }
    ASSERT_EQ(features[name].size(), 3u) << name;
  }
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_GT(features["ORB-distinct"][i], 0);
    EXPECT_LT(features["ORB-distinct"][i], features["ORB"][i]) << "frame " << i;
  }
  const ToolRun unknown = run(common + " --features SURF --out " + file("surf.txt"));
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  EXPECT_NE(unknown.output.find("--features is RISAS, ORB or ORB-distinct"), std::string::npos) << unknown.output;
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

// A recording's frame whose depth has no valid pixel (a sensor fault) stops
// each tool over recordings with one line naming that frame's files.
TEST_F(Tools, ARecordingsFrameWithoutDepthIsNamed) {
  const fs::path tum = dir / "tum_without_depth";
  fs::remove_all(tum);
  fs::copy(tumFolder(2), tum, fs::copy_options::recursive);
  const std::string depth_file = (tum / "depth" / "2.png").string();
  cv::imwrite(depth_file, cv::Mat(480, 640, CV_16UC1, cv::Scalar(0)));
  const std::string intrinsics = " --intrinsics " + file("camera-intrinsics.txt");
  for (const std::string& command :
       {"risas_odometry --tum " + tum.string() + intrinsics + " --out " + file("without_depth.txt"),
        "risas_evaluate --tum " + tum.string() + intrinsics + " --methods RISAS --no-plots --out " +
            file("without_depth"),
        "risas_benchmark --tum " + tum.string() + intrinsics + " --frames 2 --repeats 1"}) {
    const ToolRun r = run(command);
    EXPECT_EQ(r.exit_code, 1) << command << ": " << r.output;
    const std::string tool = command.substr(0, command.find(' '));
    const size_t at = r.output.find(tool + ": error: ");
    ASSERT_NE(at, std::string::npos) << command << ": " << r.output;
    EXPECT_TRUE(at == 0 || r.output[at - 1] == '\n') << "not a line of its own: " << r.output;
    const std::string error = r.output.substr(at);
    EXPECT_NE(error.find(depth_file + ": depth image has no valid pixel"), std::string::npos)
        << command << ": " << r.output;
    EXPECT_EQ(std::count(error.begin(), error.end(), '\n'), 1) << command << ": " << r.output;
  }
}

// A write that fails after the output opened (a full disk: /dev/full under
// the output's name) is an error in one line, not "written to" and exit 0
// with a short file; standard output likewise.
TEST_F(Tools, AFullDiskIsAnErrorNotASuccess) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const auto full = [](const std::string& name) { return test::fullDiskAt(dir / name); };
  const std::string extract = "risas_extract" + frameArgs("", 1) + " --intrinsics " + file("camera-intrinsics.txt");
  for (const char* name : {"full.yml", "full.yml.gz"}) {
    const ToolRun r = run(extract + " --out " + full(name));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("risas_extract: error: cannot write features file " + file(name) +
                            ": No space left on device"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("written to"), std::string::npos) << r.output;
  }
  const std::string odometry = "risas_odometry --tum " + tumFolder(3).string() + " --intrinsics " +
                               file("camera-intrinsics.txt");
  ToolRun r = run(odometry + " --out " + full("full.txt"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("cannot write trajectory " + file("full.txt") + ": No space left on device"),
            std::string::npos)
      << r.output;
  r = run(odometry + " --out " + file("fine.txt") + " --frames " + full("full.csv"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("cannot write frame table " + file("full.csv")), std::string::npos) << r.output;
  // Standard output on a full disk, the error on its own stream.
  const fs::path errors = dir / "stderr.txt";
  const int status = std::system((std::string(RISAS_BIN_DIR) + "/" + extract + " --out " + file("fine.yml") +
                                  " > /dev/full 2> " + errors.string())
                                     .c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_EQ(test::fileText(errors), "risas_extract: error: cannot write standard output: No space left on device\n");
}

// Each option is taken once and none is ignored in silence: an option
// given twice, both ways of giving the intrinsics, an option of the other
// mode, or an option where its value should be is wrong usage, exit 2, in
// one line naming it, before any work.
TEST_F(Tools, OptionsAreTakenOnceAndNoneIsIgnored) {
  const std::string extract = "risas_extract" + frameArgs("", 1);
  const std::string intrinsics = " --intrinsics " + file("camera-intrinsics.txt");
  const std::string numbers = " --fx 570 --fy 570 --cx 319.5 --cy 239.5";
  const std::map<std::string, std::string> refused = {
      {extract + intrinsics + " --fx 300 --out " + file("o.yml"),
       "risas_extract: give --intrinsics K.txt or --fx --fy --cx --cy, not both"},
      {extract + " --intrinsics --out " + file("o.yml"),
       "risas_extract: --intrinsics needs a value (K.txt), not the option --out"},
      {extract + intrinsics + " --out " + file("o.yml") + " --out=" + file("o2.yml"),
       "risas_extract: --out is given twice ('" + file("o.yml") + "', then '" + file("o2.yml") + "')"},
      {"risas_match" + frameArgs("1", 1) + frameArgs("2", 2) + intrinsics + " --cross-check --cross-check",
       "risas_match: --cross-check is given twice"},
      {"risas_evaluate --data " + dir.string() + " --gaps 2", "risas_evaluate: --gaps does not apply with --data"},
      {"risas_evaluate --data " + dir.string() + intrinsics + " --cy 2",
       "risas_evaluate: give --intrinsics K.txt or --fx --fy --cx --cy, not both"},
      {"risas_evaluate --tum " + tumFolder(3).string() + numbers + " --ground-truth raw",
       "risas_evaluate: --ground-truth does not apply with --tum"},
      {"risas_evaluate --data " + dir.string() + " --ground-truth fitted",
       "risas_evaluate: --ground-truth is corrected or raw, not 'fitted'"},
      {"risas_evaluate --tum " + tumFolder(3).string() + numbers + " --sequences rotate",
       "risas_evaluate: --sequences does not apply with --tum"},
      {"risas_evaluate --data " + dir.string() + " --study tau --methods ORB",
       "risas_evaluate: --methods does not apply with --study: the study's methods are run"},
      {"risas_evaluate --data " + dir.string() + " --sequences viewchange,illum,viewchange",
       "risas_evaluate: --sequences names 'viewchange' twice"},
      {"risas_evaluate --tum " + tumFolder(3).string() + numbers + " --gaps 1,0",
       "risas_evaluate: --gaps must be a whole number in [1, 1000000], got '0'"},
      {"risas_evaluate --data " + dir.string() + " --methods ORB,,SIFT",
       "risas_evaluate: --methods has an empty item in 'ORB,,SIFT'"},
      {"risas_benchmark" + intrinsics, "risas_benchmark: --intrinsics does not apply to the synthetic frames"},
      {"risas_benchmark --data " + dir.string() + numbers,
       "risas_benchmark: --fx does not apply with --data: its camera-intrinsics.txt is read"},
  };
  for (const auto& [command, message] : refused) {
    const ToolRun r = run(command);
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.output;
    EXPECT_EQ(r.output.rfind(message + " (see ", 0), 0u) << command << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << command << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists(file("o.yml")));
  EXPECT_FALSE(fs::exists(file("o2.yml")));
  // A value may still start with dashes when it is no option's name.
  const ToolRun r = test::runTool(extract + intrinsics + " --out --dashes.yml", "cd " + dir.string() + " && ");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "--dashes.yml"));
}

// What a list option names is there: a misspelt scene, sequence or pair
// label stops the evaluation before it starts, where it was left out.
TEST_F(Tools, EvaluationListsNameWhatIsThere) {
  const fs::path root = dir / "dataset";
  fs::create_directories(root / "texture");
  if (!fs::exists(root / "texture" / "viewchange")) fs::create_directory_symlink(dir, root / "texture" / "viewchange");
  const std::string evaluate = "risas_evaluate --data " + root.string() + " --methods ORB --no-plots --out " +
                               file("lists");
  const std::map<std::string, std::string> refused = {
      {" --scenes texture,textur", "--scenes: no folder 'textur' in " + root.string()},
      {" --scenes texture --sequences viewchange,rotat",
       "--sequences: no folder 'rotat' in " + (root / "texture").string()},
      {" --scenes texture --sequences viewchange --pairs 2,9",
       "--pairs: no pair is labelled '9' among those of " + root.string() + " and the other options"},
  };
  for (const auto& [options, message] : refused) {
    const ToolRun r = run(evaluate + options);
    EXPECT_EQ(r.exit_code, 1) << options << ": " << r.output;
    EXPECT_EQ(r.output, "risas_evaluate: error: " + message + "\n") << options;
  }
  const ToolRun r = run(evaluate + " --scenes texture --sequences viewchange --pairs 2");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("[1/1] texture/viewchange 2:"), std::string::npos) << r.output;
}

// Outputs that cannot be written are found before the work: an image name
// OpenCV has no writer for, a file where the output folder should be.
TEST_F(Tools, OutputsThatCannotBeWrittenAreFoundFirst) {
  std::ofstream(file("a_file")) << "x";
  const std::map<std::string, std::string> failing = {
      {"risas_match" + frameArgs("1", 1) + frameArgs("2", 2) + " --intrinsics " + file("camera-intrinsics.txt") +
           " --overlay " + file("overlay.xyz"),
       "risas_match: error: cannot write overlay " + file("overlay.xyz") +
           ": OpenCV has no image writer for '.xyz' (.png, .jpg, .tif, ...)"},
      {"risas_render_synthetic --out " + file("a_file"),
       "risas_render_synthetic: error: cannot make folder " + file("a_file") + ": a file of that name is there"},
      {"risas_evaluate --tum " + tumFolder(3).string() + " --intrinsics " + file("camera-intrinsics.txt") +
           " --out " + file("a_file"),
       "risas_evaluate: error: cannot make folder " + file("a_file") + ": a file of that name is there"},
  };
  for (const auto& [command, message] : failing) {
    const ToolRun r = run(command);
    EXPECT_EQ(r.exit_code, 1) << command << ": " << r.output;
    EXPECT_EQ(r.output, message + "\n") << command;
  }
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const ToolRun r = run("risas_match" + frameArgs("1", 1) + frameArgs("2", 2) + " --intrinsics " +
                        file("camera-intrinsics.txt") + " --overlay " + test::fullDiskAt(dir / "full.png"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("\nrisas_match: error: cannot write overlay " + file("full.png") +
                          ": No space left on device\n"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("overlay written"), std::string::npos) << r.output;
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
  // A ground truth that is not a rigid motion is found before the matching,
  // in one line naming its file.
  const std::string scaled = file("scaled_R.txt");
  std::ofstream(scaled) << "2 0 0\n0 2 0\n0 0 2\n";
  r = run("risas_match" + frameArgs("1", 1) + frameArgs("2", 2) + " --intrinsics " + file("camera-intrinsics.txt") +
          " --gt-rotation " + scaled + " --gt-translation " + file("T1-2.txt"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("risas_match: error: rotation file " + scaled + " does not hold a rotation"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "matched first: " << r.output;
  r = run("risas_match --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("--overlay"), std::string::npos);
}

}  // namespace
}  // namespace risas

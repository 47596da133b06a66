// The evaluation protocol and metrics on hand-made cases with known answers,
// and risas_evaluate end to end on a rendered sequence.
#include "risas/errors.hpp"
#include "risas/evaluation/evaluator.hpp"
#include "risas/evaluation/image_noise.hpp"
#include "risas/evaluation/methods.hpp"
#include "risas/evaluation/metrics.hpp"
#include "risas/evaluation/protocol.hpp"

#include "input_error.hpp"
#include "synthetic_fixtures.hpp"
#include "tool_run.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace risas::eval {
namespace {

namespace fs = std::filesystem;

// The cells of one line of the reports' CSV (no quoting: none is written).
std::vector<std::string> cellsOf(const std::string& csv_line) {
  std::vector<std::string> cells;
  std::stringstream row(csv_line);
  for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
  return cells;
}

TEST(Metrics, CurveAndAreaOfAHandMadeCase) {
  // Four positives; by ratio: correct, correct, wrong, correct.
  const std::vector<Candidate> candidates = {{0.5, true}, {0.1, true}, {0.3, false}, {0.2, true}};
  const std::vector<PrPoint> curve = prCurve(candidates, 4);
  ASSERT_EQ(curve.size(), 4u);
  EXPECT_DOUBLE_EQ(curve[0].ratio, 0.1);
  EXPECT_DOUBLE_EQ(curve[2].precision, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(curve[3].recall, 0.75);
  // 0.25 * 1 + 0.25 * 1 + 0 * 2/3 + 0.25 * 3/4
  EXPECT_DOUBLE_EQ(prAuc(curve), 0.6875);
  const PrPoint at = atThreshold(curve, 0.4);
  EXPECT_EQ(at.matches, 3);
  EXPECT_EQ(at.correct, 2);
  EXPECT_DOUBLE_EQ(at.recall, 0.5);
  EXPECT_EQ(atThreshold(curve, 0.05).matches, 0);
}

TEST(Metrics, EqualRatiosEnterTogetherAndNoPositivesMeansNoArea) {
  const std::vector<PrPoint> curve = prCurve({{0.4, true}, {0.4, false}}, 2);
  ASSERT_EQ(curve.size(), 1u);
  EXPECT_DOUBLE_EQ(curve[0].precision, 0.5);
  EXPECT_DOUBLE_EQ(prAuc(curve), 0.25);
  EXPECT_DOUBLE_EQ(prAuc(prCurve({{0.2, false}}, 0)), 0.0);
  EXPECT_TRUE(prCurve({}, 3).empty());
}

TEST(Metrics, CorrectnessUsesTheGroundTruthMotionAndFiveCentimetres) {
  Eigen::Isometry3d ref_T_query = Eigen::Isometry3d::Identity();
  ref_T_query.translation() = Eigen::Vector3d(0.1, 0.0, 0.0);
  EXPECT_TRUE(isCorrect({0.1f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f}, ref_T_query, 0.05));
  EXPECT_TRUE(isCorrect({0.14f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f}, ref_T_query, 0.05));
  EXPECT_FALSE(isCorrect({0.16f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f}, ref_T_query, 0.05));
  EXPECT_FALSE(isCorrect({0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f}, ref_T_query, 0.05));
}

TEST(Metrics, NearestNeighbourRatiosAndPositives) {
  // Reference: three descriptors at three places; queries at the same places
  // (identity motion), the second one closer to the wrong reference.
  const cv::Mat reference = (cv::Mat_<float>(3, 2) << 0, 0, 10, 0, 0, 10);
  const cv::Mat query = (cv::Mat_<float>(3, 2) << 1, 0, 6, 0, 0, 30);
  const std::vector<cv::Point3f> ref_points = {{0, 0, 1}, {1, 0, 1}, {2, 0, 1}};
  const std::vector<cv::Point3f> query_points = {{0, 0, 1}, {2, 0, 1}, {5, 5, 5}};
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  const auto candidates = nearestNeighbourCandidates(query, reference, cv::NORM_L2, query_points, ref_points, I, 0.05);
  ASSERT_EQ(candidates.size(), 3u);
  EXPECT_NEAR(candidates[0].ratio, 1.0 / 9.0, 1e-6);  // d(0,0)=1, d(10,0)=9
  EXPECT_TRUE(candidates[0].correct);
  EXPECT_NEAR(candidates[1].ratio, 4.0 / 6.0, 1e-6);  // nearest is reference 1 at (1,0,1): wrong place
  EXPECT_FALSE(candidates[1].correct);
  EXPECT_FALSE(candidates[2].correct);
  // Query 2 has no counterpart anywhere: two positives.
  EXPECT_EQ(countPositives(query_points, ref_points, I, 0.05), 2);
  EXPECT_THROW(nearestNeighbourCandidates(query, reference, cv::NORM_L2, {}, ref_points, I, 0.05), InputError);
}

TEST(Metrics, DistinctCorrectMatchesCountEachImagePointOnce) {
  // Queries 0-2 are one corner reported three times (as at three pyramid
  // levels, within 3 px of each other), all matched correctly; query 3 a
  // second point, correct; query 4 a third, wrong; query 5 a fourth point,
  // correct but above the ratio; query 6 lies apart in the query image but
  // matches the first corner's reference keypoint again.
  const std::vector<cv::Point2f> query = {{100, 100}, {101.5f, 100}, {100, 102.9f}, {200, 50}, {300, 300}, {50, 400},
                                          {400, 400}};
  const std::vector<cv::Point2f> reference = {{110, 100}, {111, 101}, {112, 100}, {210, 50}, {20, 20}, {60, 400}};
  const std::vector<Candidate> candidates = {{0.6, true, 0, 0}, {0.3, true, 1, 1}, {0.5, true, 2, 2}, {0.7, true, 3, 3},
                                             {0.2, false, 4, 4}, {0.9, true, 5, 5}, {0.4, true, 6, 1}};
  EXPECT_EQ(atThreshold(prCurve(candidates, 6), 0.8).correct, 5);
  EXPECT_EQ(distinctCorrectMatches(candidates, query, reference, 0.8), 2);  // the corner once, query 3
  EXPECT_EQ(distinctCorrectMatches(candidates, query, reference, 1.0), 3);  // and query 5
  // The lowest ratio among a point's copies is the one taken: at 0.35 only
  // query 1 has passed of the corner's.
  EXPECT_EQ(distinctCorrectMatches(candidates, query, reference, 0.35), 1);
  // 1 px apart is the same point; 4 px apart two, at the 3 px tolerance.
  EXPECT_EQ(distinctCorrectMatches({{0.1, true, 0, 0}, {0.2, true, 1, 1}}, {{0, 0}, {4, 0}}, {{0, 0}, {4, 0}}, 0.8), 2);
  EXPECT_EQ(distinctCorrectMatches({{0.1, true, 0, 0}, {0.2, true, 1, 1}}, {{0, 0}, {1, 0}}, {{0, 0}, {5, 0}}, 0.8), 1);
  EXPECT_EQ(distinctCorrectMatches({}, {}, {}, 0.8), 0);
}

TEST(Protocol, KeypointDepthIsTheMedianOfTheValid3x3) {
  cv::Mat depth(5, 5, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  depth.at<float>(1, 1) = 1.0f;
  depth.at<float>(2, 2) = 2.0f;
  depth.at<float>(3, 3) = 9.0f;
  const Intrinsics K(100, 100, 2, 2);
  EXPECT_FLOAT_EQ(keypointPoint(depth, K, {2.0f, 2.0f}).z, 2.0f);
  EXPECT_TRUE(std::isnan(keypointPoint(cv::Mat(5, 5, CV_32F, cv::Scalar(std::nanf(""))), K, {2.0f, 2.0f}).z));
  // Two valid depths either side of a jump: the farther one as measured,
  // not their mean, a point in mid-air.
  depth.at<float>(2, 2) = depth.at<float>(3, 3) = std::nanf("");
  depth.at<float>(2, 3) = 3.0f;
  EXPECT_FLOAT_EQ(keypointPoint(depth, K, {2.0f, 2.0f}).z, 3.0f);
}

TEST(Protocol, UnrotatingAnOnScreenCounterClockwiseTurn) {
  // 90 degrees counter-clockwise on screen takes the pixel right of the
  // centre to the one above it; unrotating takes it back.
  const cv::Point2f back = unrotatePixel({319.5f, 229.5f}, 90.0);
  EXPECT_NEAR(back.x, 329.5f, 1e-4);
  EXPECT_NEAR(back.y, 239.5f, 1e-4);
  const cv::Point2f same = unrotatePixel({100.0f, 50.0f}, 360.0);
  EXPECT_NEAR(same.x, 100.0f, 1e-3);
  EXPECT_NEAR(same.y, 50.0f, 1e-3);
}

TEST(Protocol, ListsPairsOfEverySequenceTypeWithTheirGroundTruth) {
  const fs::path root = fs::temp_directory_path() / ("risas_eval_layout_" + std::to_string(::getpid()));
  const auto touch = [&](const fs::path& p, const std::string& text = "x") {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
  };
  for (const std::string f : {"rgb_1", "depth_1", "rgb_2", "depth_2", "rgb_3", "depth_3"}) touch(root / "texture/scale" / (f + ".png"));
  for (int k : {1, 2, 3}) {
    touch(root / "texture/scale" / ("R1-" + std::to_string(k) + ".txt"), "1 0 0 0 1 0 0 0 1");
    touch(root / "texture/scale" / ("T1-" + std::to_string(k) + ".txt"), "9 9 9");  // raw, wrong
    touch(root / "texture/scale/corrected" / ("R1-" + std::to_string(k) + ".txt"), "1 0 0 0 1 0 0 0 1");
    touch(root / "texture/scale/corrected" / ("T1-" + std::to_string(k) + ".txt"), "0 0 0.1");
  }
  for (const std::string f : {"rgb_1", "depth_1", "rgb_1_square", "rgb_1_cube", "rgb_2", "depth_2"}) touch(root / "texture/illum" / (f + ".png"));
  for (const std::string f : {"rgb_6", "depth_6", "rgb_6_rotate30", "depth_6_rotate30"}) touch(root / "texture/synthetic_rotate" / (f + ".png"));

  const std::vector<Pair> pairs = listPairs(root.string(), {"texture", "geometry"}, evaluatedSequences());
  std::vector<std::string> labels;
  for (const Pair& p : pairs) labels.push_back(p.sequence + ":" + p.label);
  EXPECT_EQ(labels, (std::vector<std::string>{"illum:square", "illum:cube", "illum:2", "scale:2", "scale:3",
                                               "synthetic_rotate:rotate30"}));
  const Pair& scale3 = pairs[4];
  EXPECT_NEAR(scale3.ref_T_query.translation().z(), 0.1, 1e-12) << "corrected/ poses come first";
  EXPECT_EQ(fs::path(pairs[1].query.depth).filename(), "depth_1.png") << "transformed images use depth_1";
  EXPECT_DOUBLE_EQ(pairs[5].image_rotation_deg, 30.0);
  EXPECT_EQ(fs::path(pairs[5].reference.rgb).filename(), "rgb_6.png");
  EXPECT_TRUE(pairs[5].ref_T_query.isApprox(Eigen::Isometry3d::Identity()));
  // The names drawn noise is keyed on: the colour image's path under the root.
  EXPECT_EQ(pairs[1].reference.name, "texture/illum/rgb_1.png");
  EXPECT_EQ(pairs[1].query.name, "texture/illum/rgb_1_cube.png");
  EXPECT_EQ(pairs[5].query.name, "texture/synthetic_rotate/rgb_6_rotate30.png");
  EXPECT_EQ(pairs[5].query.noiseKey(), pairs[5].query.name);
  FramePaths by_hand;  // listed without a name: its noise is keyed on its path
  by_hand.rgb = (root / "texture/scale/rgb_2.png").string();
  EXPECT_EQ(by_hand.noiseKey(), by_hand.rgb);
  fs::remove_all(root);
}

TEST(Methods, KnowsItsMethodsAndRejectsOthers) {
  const std::vector<std::string> names = methodNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "RISAS"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "ORB"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "ORB-distinct"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "ORB-distinct+RISAS"), names.end());
  EXPECT_EQ(makeMethod("ORB", RisasParams())->norm(), cv::NORM_HAMMING);
  EXPECT_EQ(makeMethod("RISAS", RisasParams())->norm(), cv::NORM_L2);
  EXPECT_THROW(makeMethod("SURF", RisasParams()), InputError);
}

TEST(Metrics, OnePerImagePointKeepsTheStrongestOfEachPoint) {
  // A corner at three levels (responses 5, 9, 7 within 3 px of each other),
  // a point 3 px from the strongest copy (the same point: the tolerance is
  // inclusive), one 3.5 px from it, and two equal responses 10 px apart.
  const std::vector<cv::KeyPoint> keypoints = {
      {{100, 100}, 31, -1, 5}, {{101.5f, 100}, 37, -1, 9}, {{100, 102}, 45, -1, 7}, {{101.5f, 103}, 31, -1, 8},
      {{105, 100}, 31, -1, 6}, {{200, 50}, 31, -1, 2},     {{210, 50}, 31, -1, 2}};
  const std::vector<cv::KeyPoint> kept = onePerImagePoint(keypoints);
  ASSERT_EQ(kept.size(), 4u);
  EXPECT_EQ(kept[0].pt, cv::Point2f(101.5f, 100));  // the corner's strongest copy, at its own size
  EXPECT_FLOAT_EQ(kept[0].size, 37.0f);
  EXPECT_EQ(kept[1].pt, cv::Point2f(105, 100));
  EXPECT_EQ(kept[2].pt, cv::Point2f(200, 50));  // equal responses in their order
  EXPECT_EQ(kept[3].pt, cv::Point2f(210, 50));
  EXPECT_TRUE(onePerImagePoint({}).empty());
  EXPECT_EQ(onePerImagePoint(keypoints, 0.5).size(), keypoints.size());
}

TEST(Methods, OrbDistinctDescribesEachOfOrbsPointsOnce) {
  SyntheticScene scene = SyntheticScene::demo();
  const RgbdFrame frame = test::renderFrame(scene, test::demoCamera());
  const MethodOutput orb = makeMethod("ORB", RisasParams())->run(frame, cv::Mat());
  for (const std::string name : {"ORB-distinct", "ORB-distinct+RISAS"}) {
    const auto method = makeMethod(name, RisasParams());
    const MethodOutput out = method->run(frame, cv::Mat());
    ASSERT_FALSE(out.pixels.empty()) << name;
    EXPECT_EQ(out.descriptors.rows, static_cast<int>(out.pixels.size())) << name;
    EXPECT_LT(out.pixels.size(), orb.pixels.size()) << name;
    for (size_t i = 0; i < out.pixels.size(); ++i) {
      for (size_t j = 0; j < i; ++j) ASSERT_GT(cv::norm(out.pixels[i] - out.pixels[j]), kSamePointPixels) << name;
    }
  }
  EXPECT_EQ(makeMethod("ORB-distinct", RisasParams())->norm(), cv::NORM_HAMMING);
  EXPECT_EQ(makeMethod("ORB-distinct+RISAS", RisasParams())->norm(), cv::NORM_L2);
  // Every one of ORB's points keeps a keypoint of its own: ORB's 1000 are
  // copies of fewer points (docs/evaluation.md, "Correct matches, each image
  // point once").
  const MethodOutput distinct = makeMethod("ORB-distinct", RisasParams())->run(frame, cv::Mat());
  for (const cv::Point2f& p : orb.pixels) {
    double nearest = 1e9;
    for (const cv::Point2f& q : distinct.pixels) nearest = std::min(nearest, cv::norm(p - q));
    ASSERT_LE(nearest, kSamePointPixels);
  }
}

// The noise withImageNoise adds is what it says: zero-mean, sigma grey
// levels, independent between channels, rounded and saturated (not wrapped)
// at 0 and 255; drawn again only for another seed or frame.
TEST(ImageNoise, AddsZeroMeanGaussianNoiseOfSigmaToEachChannelSaturated) {
  const cv::Mat grey(200, 300, CV_8UC3, cv::Scalar(128, 128, 128));
  const cv::Mat noisy = withImageNoise(grey, 10.0, 1, 7);
  ASSERT_EQ(noisy.type(), CV_8UC3);
  ASSERT_EQ(noisy.size(), grey.size());
  cv::Mat difference;
  noisy.convertTo(difference, CV_64FC3, 1.0, -128.0);
  cv::Scalar mean, sd;
  cv::meanStdDev(difference, mean, sd);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(mean[c], 0.0, 0.15) << "channel " << c;
    EXPECT_NEAR(sd[c], std::sqrt(100.0 + 1.0 / 12.0), 0.2) << "channel " << c;  // plus the rounding's
  }
  std::vector<cv::Mat> channels;
  cv::split(difference, channels);
  EXPECT_LT(std::abs(channels[0].dot(channels[1])) / (channels[0].total() * sd[0] * sd[1]), 0.02);
  EXPECT_LT(std::abs(channels[1].dot(channels[2])) / (channels[1].total() * sd[1] * sd[2]), 0.02);
  // The same draw for the same seed and frame, another for either changed.
  const double values = static_cast<double>(grey.total() * grey.channels());
  EXPECT_EQ(cv::norm(withImageNoise(grey, 10.0, 1, 7), noisy, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::countNonZero(withImageNoise(grey, 10.0, 2, 7).reshape(1) != noisy.reshape(1)), 0.8 * values);
  EXPECT_GT(cv::countNonZero(withImageNoise(grey, 10.0, 1, 8).reshape(1) != noisy.reshape(1)), 0.8 * values);
  EXPECT_EQ(cv::norm(withImageNoise(grey, 0.0, 1, 7), grey, cv::NORM_INF), 0.0);
  // Black stays at 0 where the noise is negative, about half the pixels; a
  // wrap-around would have put them near 255.
  const cv::Mat black(100, 100, CV_8UC1, cv::Scalar(0));
  const cv::Mat dark = withImageNoise(black, 10.0, 3, 0);
  const double zeros = 1.0 - cv::countNonZero(dark) / 10000.0;
  EXPECT_GT(zeros, 0.45);
  EXPECT_LT(zeros, 0.58);
  double highest = 0.0;
  cv::minMaxLoc(dark, nullptr, &highest);
  EXPECT_LT(highest, 80.0);
  // A sigma that is no grey level, or an image that is not 8-bit: one line.
  for (const double sigma : {-1.0, std::nan(""), 256.0}) {
    EXPECT_NE(test::inputErrorOf([&] { withImageNoise(grey, sigma, 1, 0); }).find("image noise sigma must be 0 to 255"),
              std::string::npos)
        << sigma;
  }
  EXPECT_NE(test::inputErrorOf([] { withImageNoise(cv::Mat(4, 4, CV_16UC1, cv::Scalar(0)), 1.0, 1, 0); })
                .find("image noise is for 8-bit images"),
            std::string::npos);
  EXPECT_NE(test::inputErrorOf([] { ImageNoise{-1.0, 0}.validate(); }).find("image noise sigma must be 0 to 255"),
            std::string::npos);
}

// An image without a frame number is indexed by its name: 64-bit FNV-1a
// (its published value for "a"), the same name the same index.
TEST(ImageNoise, IndexOfANameIsItsFnv1aHash) {
  EXPECT_EQ(imageNoiseIndex(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(imageNoiseIndex("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(imageNoiseIndex("texture/viewchange/rgb_2.png"), imageNoiseIndex("texture/viewchange/rgb_2.png"));
  EXPECT_NE(imageNoiseIndex("texture/viewchange/rgb_2.png"), imageNoiseIndex("geometry/viewchange/rgb_2.png"));
}

TEST(Evaluator, AMissIsPreferredByTheDepthOnlyWhenItsPoseFitsClearlyBetter) {
  PoseRecovery pose;
  pose.estimated = true;
  pose.error = {9.0, 0.04};  // missed: 9 degrees off
  EXPECT_TRUE(missPreferredByDepth(pose, 0.80, 0.45));
  EXPECT_FALSE(missPreferredByDepth(pose, 0.47, 0.45));  // better, but by less than kDepthPreference
  EXPECT_FALSE(missPreferredByDepth(pose, 0.80, NAN));   // not checked (synthetic_rotate)
  pose.error = {1.0, 0.01};                              // not a miss
  EXPECT_FALSE(missPreferredByDepth(pose, 0.80, 0.45));
  EXPECT_FALSE(missPreferredByDepth(PoseRecovery(), 0.80, 0.45));  // no estimate: a miss the depth cannot judge
}

TEST(Evaluator, PoseSharesCountEachSeedOnce) {
  // Four seeds: recovered closely, recovered at 3 degrees, missed where the
  // depth prefers the estimate, missed without an estimate.
  std::vector<PoseRecovery> poses(4);
  for (int k = 0; k < 3; ++k) poses[static_cast<size_t>(k)].estimated = true;
  poses[0].error = {0.5, 0.005};
  poses[1].error = {3.0, 0.01};
  poses[2].error = {9.0, 0.04};
  const PoseShares shares = poseShares(poses, {0.9, 0.9, 0.8, NAN}, 0.45);
  EXPECT_EQ(shares.recovered, 0.5);
  EXPECT_EQ(shares.recovered_closely, 0.25);
  EXPECT_EQ(shares.missed_preferred_by_depth, 0.25);
  EXPECT_EQ(shares.missed(), 0.5);
  EXPECT_EQ(poseShares({poses[2]}, {0.8}, NAN).missed_preferred_by_depth, 0.0);  // no truth to compare with
}

// risas_evaluate on three rendered frames in the dataset layout: exact poses,
// so RISAS must find its correspondences; every report is written.
TEST(EvaluateTool, RunsEndToEndOnARenderedSequence) {
  const fs::path root = fs::temp_directory_path() / ("risas_eval_e2e_" + std::to_string(::getpid()));
  const fs::path sequence = root / "texture" / "viewchange";
  const std::string bin = RISAS_BIN_DIR;
  ASSERT_EQ(std::system((bin + "/risas_render_synthetic --out " + sequence.string() + " --frames 3 --step-deg 4 > /dev/null").c_str()), 0);
  fs::rename(sequence / "camera-intrinsics.txt", root / "camera-intrinsics.txt");
  std::string methods = "RISAS,ORB";
  if (havePcl()) methods += ",RISAS+CSHOT";
  const fs::path out = root / "out";
  const test::ToolRun run =
      test::runTool("risas_evaluate --data " + root.string() + " --out " + out.string() + " --methods " + methods);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("[2/2] texture/viewchange 3:"), std::string::npos) << run.output;
  for (const char* file : {"pairs.csv", "curves.csv", "summary.csv", "summary.md", "scale.csv"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file;
  }
  std::ifstream summary(out / "summary.csv");
  std::string line;
  std::getline(summary, line);
  double risas_auc = -1.0;
  int rows = 0;
  while (std::getline(summary, line)) {
    ++rows;
    const std::vector<std::string> cells = cellsOf(line);
    // scene .. recall, correct and distinct correct matches, keypoints,
    // ms_per_frame, then success at 5 deg / 5 cm and 2 deg / 2 cm, mean
    // inliers, repeatability, misses and those the depth prefers.
    ASSERT_EQ(cells.size(), 17u) << line;
    EXPECT_EQ(cells[3], "2") << "two pairs per method";
    const double correct = std::stod(cells[7]), distinct = std::stod(cells[8]);
    EXPECT_LE(distinct, correct) << line;
    if (cells[2] == "ORB") {
      // ORB finds many corners again at its coarser pyramid levels, a few
      // pixels from where level 0 found them: fewer distinct points.
      EXPECT_LT(distinct, 0.8 * correct) << line;
    }
    if (cells[2] != "RISAS") continue;
    risas_auc = std::stod(cells[4]);
    // RISAS's non-maximum suppression keeps its keypoints apart.
    EXPECT_GT(distinct, 0.9 * correct) << line;
    // Rendered frames 4 and 8 degrees from frame 1 with exact poses: the
    // motion comes back from RISAS's matches on both pairs, with each of the
    // default 8 RANSAC seeds.
    EXPECT_EQ(std::stod(cells[11]), 1.0) << line;
    EXPECT_GT(std::stod(cells[13]), 20.0) << "mean inliers: " << line;
    EXPECT_GT(std::stod(cells[14]), 0.3) << "repeatability: " << line;
    EXPECT_LE(std::stod(cells[14]), 1.0) << line;
    EXPECT_EQ(cells[15], "0") << "no miss on exact poses: " << line;
    EXPECT_EQ(cells[16], "0") << line;
  }
  EXPECT_EQ(rows, havePcl() ? 3 : 2);
  EXPECT_GT(risas_auc, 0.3) << "RISAS on exact synthetic poses (measured 0.49; random descriptors give about 0)";
  if (std::system("/usr/bin/python3 -c 'import matplotlib' 2> /dev/null") == 0) {
    EXPECT_TRUE(fs::exists(out / "pr_texture_viewchange.png")) << run.output;
  }
  // The layout study: one RISAS per rings x rank groups, each named by them.
  const fs::path layout = root / "layout";
  ASSERT_EQ(std::system((bin + "/risas_evaluate --data " + root.string() + " --study layout --no-plots --out " +
                         layout.string() + " > /dev/null 2>&1").c_str()),
            0);
  std::ifstream layout_summary(layout / "summary.csv");
  std::getline(layout_summary, line);
  std::vector<std::string> variants;
  while (std::getline(layout_summary, line)) {
    const std::vector<std::string> cells = cellsOf(line);
    variants.push_back(cells.at(0) + "," + cells.at(1) + "," + cells.at(2));  // scene, sequence, method
  }
  const std::vector<std::string> expected_variants = [] {
    std::vector<std::string> names;
    for (int rings : {1, 2, 3}) {
      for (int bins : {2, 4, 6, 8}) {
        names.push_back("texture,viewchange,RISAS(n_ring=" + std::to_string(rings) + "/n_bin=" + std::to_string(bins) + ")");
      }
    }
    return names;
  }();
  EXPECT_EQ(variants, expected_variants);
  // The reprojection refit: named in the pose table's title, and on exact
  // rendered poses it recovers every pair with every seed as the default does.
  const fs::path refit = root / "refit";
  ASSERT_EQ(std::system((bin + "/risas_evaluate --data " + root.string() + " --methods RISAS --pose-refit reprojection" +
                         " --no-plots --out " + refit.string() + " > /dev/null 2>&1").c_str()),
            0);
  const std::string refit_md = test::fileText(refit / "summary.md");
  EXPECT_NE(refit_md.find("(2 deg / 2 cm), refitted on the reprojection errors, % of pairs"), std::string::npos)
      << refit_md;
  const std::string default_md = test::fileText(out / "summary.md");
  EXPECT_EQ(default_md.find("reprojection"), std::string::npos) << default_md;
  std::ifstream refit_summary(refit / "summary.csv");
  std::getline(refit_summary, line);
  ASSERT_TRUE(std::getline(refit_summary, line));
  EXPECT_EQ(std::stod(cellsOf(line).at(11)), 1.0) << line;
  // The ground truth and the intrinsics as given: corrected/ poses 9 m off
  // fail every pair unless --ground-truth raw passes them over for the
  // rendered (raw) ones, and a focal length a sixth of the rendered one
  // bends the back-projected points so that no pose is right.
  const fs::path sequence_corrected = sequence / "corrected";
  fs::create_directories(sequence_corrected);
  for (int k : {2, 3}) {
    std::ofstream(sequence_corrected / ("R1-" + std::to_string(k) + ".txt")) << "1 0 0\n0 1 0\n0 0 1\n";
    std::ofstream(sequence_corrected / ("T1-" + std::to_string(k) + ".txt")) << "9\n0\n0\n";
  }
  const auto poseSuccess = [&](const std::string& options) {
    const fs::path dir = root / "ground_truth";
    const std::string command = bin + "/risas_evaluate --data " + root.string() + " --methods RISAS --ransac-seeds 1" +
                                options + " --no-plots --out " + dir.string() + " > /dev/null 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream csv(dir / "summary.csv");
    std::string row;
    std::getline(csv, row);
    std::getline(csv, row);
    return std::stod(cellsOf(row).at(11));
  };
  EXPECT_EQ(poseSuccess(""), 0.0) << "corrected/ is the default";
  EXPECT_EQ(poseSuccess(" --ground-truth raw"), 1.0);
  EXPECT_EQ(poseSuccess(" --ground-truth raw --fx 95 --fy 95 --cx 319.5 --cy 239.5"), 0.0);
  // Wrong usage (exit 2) and missing data (1) fail in one line, and leave
  // no output folder behind.
  const fs::path never = root / "never";
  for (const auto& [options, exit_code, error] : std::vector<std::tuple<std::string, int, std::string>>{
           {" --pose-refit icp", 2, "--pose-refit is umeyama or reprojection, not 'icp'"},
           {" --study rings", 2, "--study is bins, layout or tau, not 'rings'"},
           {" --methods SURF", 1, "unknown method 'SURF'"},
           {" --ransac-seeds 0", 2, "--ransac-seeds must be a whole number in [1, 1000], got '0'"},
           {" --scenes texture --sequences none", 1, "--sequences: no folder 'none'"}}) {
    const test::ToolRun run =
        test::runTool("risas_evaluate --data " + root.string() + options + " --out " + never.string());
    EXPECT_EQ(run.exit_code, exit_code) << options;
    EXPECT_NE(run.output.find("risas_evaluate: "), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(error), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(never)) << options;
  }
  const test::ToolRun missing =
      test::runTool("risas_evaluate --data " + (root / "none").string() + " --out " + never.string());
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("risas_evaluate: error: no folder " + (root / "none").string()), std::string::npos)
      << missing.output;
  EXPECT_FALSE(fs::exists(never));
  fs::remove_all(root);
}

// risas_evaluate --image-noise: each image's noise is drawn from the seed
// and its path under the root, so it is the same whichever pairs are asked
// for and wherever the data lies, and another seed draws other noise. ORB
// alone, one RANSAC seed: the tables are the noise's, not RANSAC's.
TEST(EvaluateTool, ImageNoiseIsEachImagesWhereverTheDataLies) {
  const fs::path root = fs::temp_directory_path() / ("risas_eval_noise_" + std::to_string(::getpid()));
  const fs::path sequence = root / "a" / "texture" / "viewchange";
  const std::string render = "risas_render_synthetic --frames 3 --step-deg 4 --out " + sequence.string();
  ASSERT_EQ(test::runTool(render).exit_code, 0);
  fs::rename(sequence / "camera-intrinsics.txt", root / "a" / "camera-intrinsics.txt");
  fs::copy(root / "a", root / "b", fs::copy_options::recursive);
  // pairs.csv's rows by pair label, without the timing (ms_per_frame), and
  // curves.csv; what the tool printed in `said`.
  std::string said;
  const auto tables = [&](const std::string& data, const std::string& options) {
    const fs::path out = root / "out";
    fs::remove_all(out);
    const test::ToolRun run = test::runTool("risas_evaluate --methods ORB --ransac-seeds 1 --no-plots --data " +
                                            (root / data).string() + " --out " + out.string() + options);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    said = run.output;
    std::stringstream pairs(test::fileText(out / "pairs.csv"));
    std::string line;
    std::getline(pairs, line);
    const std::vector<std::string> header = cellsOf(line);
    std::map<std::string, std::vector<std::string>> rows;
    while (std::getline(pairs, line)) {
      std::vector<std::string> row = cellsOf(line);
      EXPECT_EQ(row.size(), header.size()) << line;
      const std::string label = row.at(2);
      row.erase(row.begin() + (std::find(header.begin(), header.end(), "ms_per_frame") - header.begin()));
      rows[label] = row;
    }
    return std::make_pair(rows, test::fileText(out / "curves.csv"));
  };
  const auto noisy = tables("a", " --image-noise 5 --noise-seed 1");
  ASSERT_EQ(noisy.first.size(), 2u);
  EXPECT_EQ(tables("b", " --image-noise 5 --noise-seed 1"), noisy) << "another root, the same noise";
  EXPECT_EQ(tables("a", " --image-noise 5 --noise-seed 1 --pairs 3").first.at("3"), noisy.first.at("3"))
      << "rgb_1 and rgb_3 get their noise whether or not rgb_2 is read first";
  EXPECT_NE(tables("a", " --image-noise 5 --noise-seed 2").second, noisy.second);
  EXPECT_NE(said.find("Colour images with grey noise of sigma 5 (noise seed 2) before their features"),
            std::string::npos)
      << said;
  EXPECT_NE(tables("a", "").second, noisy.second);
  EXPECT_EQ(said.find("grey noise"), std::string::npos) << said;
  // Wrong noise options: one line.
  for (const auto& [options, error] : std::vector<std::pair<std::string, std::string>>{
           {" --image-noise 300", "risas_evaluate: --image-noise is 0 to 255 grey levels, not 300"},
           {" --noise-seed 3", "risas_evaluate: --noise-seed does not apply without --image-noise"}}) {
    const test::ToolRun run = test::runTool("risas_evaluate --data " + (root / "a").string() + options);
    EXPECT_EQ(run.exit_code, 2) << options;
    EXPECT_NE(run.output.find(error), std::string::npos) << run.output;
  }
  fs::remove_all(root);
}

}  // namespace
}  // namespace risas::eval

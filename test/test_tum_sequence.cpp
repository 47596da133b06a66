// TUM RGB-D folders (issue 16): parsing, association of colour, depth and
// ground truth by nearest stamp, the pairs of the evaluation, and clear
// errors for what is wrong, on small sequences written by the test.
#include "input_error.hpp"

#include "risas/errors.hpp"
#include "risas/evaluation/protocol.hpp"
#include "risas/evaluation/median.hpp"
#include "risas/evaluation/trajectory.hpp"
#include "risas/tum_sequence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace risas {
namespace {
namespace fs = std::filesystem;

class Tum : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("risas_tum_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "rgb");
    fs::create_directories(dir_ / "depth");
    // Colour at 10.00, 10.10, 10.20, 10.30, 10.40; depth 5 ms later, but
    // none near 10.20; ground truth every 10 ms from 9.9 to 10.35 (none
    // near 10.40). The camera moves 0.1 m along x per 0.1 s.
    std::string rgb = "# color images\n# timestamp filename\n", depth = "# depth\n\n";
    for (int k = 0; k < 5; ++k) {
      const std::string s = stamp(10.0 + 0.1 * k), d = stamp(10.005 + 0.1 * k);
      touch("rgb/" + s + ".png");
      rgb += s + " rgb/" + s + ".png\n";
      if (k == 2) continue;
      touch("depth/" + d + ".png");
      depth += d + " depth/" + d + ".png\n";
    }
    write("rgb.txt", rgb);
    write("depth.txt", depth);
    std::string gt = "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n";
    for (int k = 0; k <= 45; ++k) {
      const double t = 9.9 + 0.01 * k;
      gt += stamp(t) + " " + std::to_string(t - 10.0) + " 0.5 1.0 0 0 0 1\n";
    }
    write("groundtruth.txt", gt);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string stamp(double t) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6f", t);
    return text;
  }
  void touch(const std::string& name) const { std::ofstream(dir_ / name) << "x"; }
  void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }
  std::string dir() const { return dir_.string(); }
  fs::path dir_;
};

const auto errorOf = [](auto&& call) { return test::inputErrorOf(call); };

TEST_F(Tum, PairsColourAndDepthByNearestStampAndTakesTheNearestPose) {
  const TumSequence s = readTumSequence(dir());
  ASSERT_EQ(s.frames.size(), 4u);  // 10.20 has no depth within 0.02 s
  EXPECT_EQ(s.unmatched_rgb, 1);
  EXPECT_EQ(s.unmatched_depth, 0);
  EXPECT_EQ(s.without_pose, 1);  // 10.40: the last ground truth is at 10.35
  EXPECT_DOUBLE_EQ(s.frames[0].stamp, 10.0);
  EXPECT_NEAR(s.frames[0].depth_stamp, 10.005, 1e-9);
  EXPECT_NE(s.frames[2].rgb.find("10.300000.png"), std::string::npos);
  EXPECT_NE(s.frames[2].depth.find("10.305000.png"), std::string::npos);
  ASSERT_TRUE(s.frames[1].world_T_camera);
  EXPECT_NEAR(s.frames[1].world_T_camera->translation().x(), 0.1, 1e-9);
  EXPECT_NEAR(s.frames[1].world_T_camera->translation().z(), 1.0, 1e-12);
  EXPECT_FALSE(s.frames[3].world_T_camera);
  // The file's poses, all 46 in its order, for scoring a trajectory.
  EXPECT_TRUE(s.has_ground_truth);
  ASSERT_EQ(s.ground_truth.size(), 46u);
  EXPECT_DOUBLE_EQ(s.ground_truth.front().stamp, 9.9);
  EXPECT_NEAR(s.ground_truth.back().world_T_camera.translation().x(), 0.35, 1e-9);
  EXPECT_EQ(leftOutOf(s), "1 of 5 colour images have no depth image within 0.02 s; "
                          "1 of 4 frames have no ground-truth pose within 0.02 s");
  write("depth.txt", "# depth\n10.005000 depth/10.005000.png\n10.305000 depth/10.305000.png\n");
  fs::remove(dir_ / "groundtruth.txt");  // no ground truth: no frame lacks one
  EXPECT_EQ(leftOutOf(readTumSequence(dir(), 0.01)), "3 of 5 colour images have no depth image within 0.01 s");
  EXPECT_TRUE(readTumSequence(dir()).ground_truth.empty());
  TumSequence whole;
  whole.frames.resize(3);
  EXPECT_EQ(leftOutOf(whole), "");
}

// A ground truth whose clock runs 0.1 s early: shifted by 0.1 s, its stamps
// 9.9 .. 10.35 become 10.0 .. 10.45, so that each frame takes the pose
// stamped 0.1 s before it and the last frame (10.40) has one too.
TEST_F(Tum, TheTruthOffsetShiftsTheGroundTruthsStampsBeforeThePairing) {
  const TumSequence s = readTumSequence(dir(), kTumMaxDifference, 0.1);
  ASSERT_EQ(s.frames.size(), 4u);
  EXPECT_EQ(s.without_pose, 0);
  const std::vector<double> x = {-0.1, 0.0, 0.2, 0.3};  // frames 10.0, 10.1, 10.3, 10.4
  for (size_t k = 0; k < x.size(); ++k) {
    ASSERT_TRUE(s.frames[k].world_T_camera) << k;
    EXPECT_NEAR(s.frames[k].world_T_camera->translation().x(), x[k], 1e-9) << k;
  }
  // The poses kept for scoring are shifted alike, each pose unchanged.
  const TumSequence as_given = readTumSequence(dir());
  ASSERT_EQ(s.ground_truth.size(), as_given.ground_truth.size());
  for (size_t k = 0; k < s.ground_truth.size(); ++k) {
    EXPECT_DOUBLE_EQ(s.ground_truth[k].stamp, as_given.ground_truth[k].stamp + 0.1) << k;
    EXPECT_EQ(s.ground_truth[k].world_T_camera.matrix(), as_given.ground_truth[k].world_T_camera.matrix()) << k;
  }
  // Shifted the other way, the first frames lose theirs: 9.9 .. 10.35
  // become 9.8 .. 10.25.
  EXPECT_EQ(readTumSequence(dir(), kTumMaxDifference, -0.1).without_pose, 2);
  for (double offset : {std::nan(""), HUGE_VAL}) {
    EXPECT_EQ(errorOf([&] { readTumSequence(dir(), kTumMaxDifference, offset); }),
              "the ground truth's offset for " + dir() + " is not a finite number of seconds");
  }
}

TEST_F(Tum, AssociationTakesTheClosestStampsFirstAndEachOnce) {
  // 1.000 is closest to 1.004 and 1.010 to 1.011; 1.020 would also be
  // near 1.011 but that one is taken.
  const auto m = associateStamps({1.000, 1.010, 1.020}, {1.011, 1.004}, 0.02);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0], std::make_pair(size_t{0}, size_t{1}));
  EXPECT_EQ(m[1], std::make_pair(size_t{1}, size_t{0}));
  EXPECT_TRUE(associateStamps({1.0}, {1.5}, 0.02).empty());
}

TEST_F(Tum, EvaluationPairsCarryTheRelativeMotion) {
  const std::vector<eval::Pair> pairs = eval::listTumPairs(dir(), readTumSequence(dir()), {1, 2});
  // gap 1: (0,1), (1,2); (2,3) has no pose for 3. gap 2: (0,2).
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[0].sequence, "gap1");
  EXPECT_EQ(pairs[0].label, "0+1");
  EXPECT_EQ(pairs[2].sequence, "gap2");
  EXPECT_EQ(pairs[2].scene, dir_.filename().string());
  EXPECT_DOUBLE_EQ(pairs[0].query.depth_units_per_metre, kTumDepthUnitsPerMetre);
  // The name drawn noise is keyed on: the path as rgb.txt has it, under the folder.
  EXPECT_EQ(pairs[2].query.name, "rgb/" + fs::path(pairs[2].query.rgb).filename().string());
  // Frame 0 at x = 0, frame 2 (10.30) at x = 0.3: p_ref = p_query + (0.3, 0, 0).
  EXPECT_NEAR(pairs[2].ref_T_query.translation().x(), 0.3, 1e-9);
  EXPECT_TRUE(pairs[2].ref_T_query.linear().isIdentity(1e-12));
  EXPECT_NE(errorOf([&] { eval::listTumPairs(dir(), readTumSequence(dir()), {0}); }).find("gap must be positive"),
            std::string::npos);
}

TEST_F(Tum, MissingAndMalformedFilesAreNamed) {
  fs::remove(dir_ / "groundtruth.txt");
  EXPECT_EQ(readTumSequence(dir()).without_pose, 4);  // no ground truth: frames without poses
  write("groundtruth.txt", "10.0 0 0 0 0 0 0\n");
  EXPECT_NE(errorOf([&] { readTumSequence(dir()); }).find("groundtruth.txt line 1: expected 'timestamp tx ty tz qx qy qz qw'"),
            std::string::npos);
  write("groundtruth.txt", "10.0 0 0 nan 0 0 0 1\n");
  EXPECT_NE(errorOf([&] { readTumSequence(dir()); }).find("'nan' is not a finite number"), std::string::npos);
  write("groundtruth.txt", "");
  write("depth.txt", "# header\n10.005 depth/missing.png\n");
  EXPECT_NE(errorOf([&] { readTumSequence(dir()); }).find("depth.txt line 2: no file"), std::string::npos);
  write("depth.txt", "10.005\n");
  EXPECT_NE(errorOf([&] { readTumSequence(dir()); }).find("depth.txt line 1: expected 'timestamp filename'"), std::string::npos);
  write("depth.txt", "# nothing\n");
  EXPECT_NE(errorOf([&] { readTumSequence(dir()); }).find("no colour image"), std::string::npos);
  fs::remove(dir_ / "rgb.txt");
  EXPECT_NE(errorOf([&] { readTumSequence(dir()); }).find("no rgb.txt in"), std::string::npos);
  EXPECT_NE(errorOf([&] { readTumSequence((dir_ / "nope").string()); }).find("no folder"), std::string::npos);
}

// Ten poses about 0.1 m apart, mostly along x, turning 2 degrees about y each.
std::vector<StampedPose> line() {
  std::vector<StampedPose> poses;
  for (int k = 0; k < 10; ++k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(k * 2.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(0.1 * k, 0.03 * (k % 4), 1.0 + 0.05 * (k % 3));  // not on one line
    poses.push_back({100.0 + 0.1 * k, T});
  }
  return poses;
}

TEST_F(Tum, TrajectoriesRoundTripAndTheirErrorIsTheBenchmarks) {
  const std::vector<StampedPose> truth = line();
  writeTumTrajectory(dir() + "/t.txt", truth);
  const std::vector<StampedPose> back = readTumTrajectory(dir() + "/t.txt");
  ASSERT_EQ(back.size(), truth.size());
  for (size_t k = 0; k < truth.size(); ++k) {
    EXPECT_NEAR(back[k].stamp, truth[k].stamp, 1e-6);
    EXPECT_TRUE(back[k].world_T_camera.isApprox(truth[k].world_T_camera, 1e-6));
  }
  // An estimate in another world frame: no error once aligned, none relative.
  const Eigen::Isometry3d G = Eigen::Translation3d(1.0, -2.0, 0.5) * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  std::vector<StampedPose> moved = truth;
  for (StampedPose& p : moved) p.world_T_camera = G * p.world_T_camera;
  eval::TrajectoryError e = eval::trajectoryError(eval::associate(moved, truth), 1);
  EXPECT_EQ(e.poses, 10);
  EXPECT_LT(e.ate_rmse, 1e-9);
  EXPECT_LT(e.rpe_translation_rmse, 1e-9);
  EXPECT_LT(e.rpe_rotation_rmse_deg, 1e-6);
  EXPECT_TRUE(e.truth_T_estimate.isApprox(G.inverse(), 1e-9));
  // One pose 10 cm off in y: the two pairs through it are 10 cm wrong,
  // RPE = sqrt(2 x 0.01 / 9).
  std::vector<StampedPose> bumped = truth;
  bumped[5].world_T_camera.translation().y() += 0.1;
  e = eval::trajectoryError(eval::associate(bumped, truth), 1);
  EXPECT_EQ(e.rpe_pairs, 9);
  EXPECT_NEAR(e.rpe_translation_rmse, std::sqrt(2 * 0.01 / 9), 1e-9);
  EXPECT_NEAR(e.rpe_rotation_rmse_deg, 0.0, 1e-6);
  EXPECT_GT(e.ate_max, 0.05);
  // Stamps 5 ms off still associate; fewer than 3 poses is an error.
  for (StampedPose& p : moved) p.stamp += 0.005;
  EXPECT_EQ(eval::associate(moved, truth).estimate.size(), 10u);
  EXPECT_THROW(eval::trajectoryError(eval::associate({moved[0], moved[1]}, truth)), InputError);
  write("bad.txt", "100.0 1 2 3\n");
  EXPECT_NE(errorOf([&] { readTumTrajectory(dir() + "/bad.txt"); }).find("bad.txt line 1"), std::string::npos);
}

// The median of an odd count is its middle value, of an even count the mean
// of the two middle ones; the order of the values does not matter.
TEST(Median, IsTheMiddleValueOrTheMeanOfTheTwoMiddleOnes) {
  EXPECT_DOUBLE_EQ(eval::median({0.05, 0.01, 0.03}), 0.03);
  EXPECT_DOUBLE_EQ(eval::median({0.04, 0.01, 0.5, 0.02}), 0.03);  // an outlier moves the mean, not the median
  EXPECT_DOUBLE_EQ(eval::median({6.0, 1.0, 5.0, 2.0, 4.0, 3.0}), 3.5);  // unsorted, the middle two apart
  EXPECT_DOUBLE_EQ(eval::median({7.0}), 7.0);
  EXPECT_THROW(eval::median({}), InputError);
}

// An estimate whose errors are drawn from the covariances it reports, in
// its own world (the first camera), the truth in another: the ratios are 1.
// The same estimate claiming a quarter of the variance is overconfident by 4.
TEST(CovarianceConsistency, IsOneForErrorsDrawnFromTheCovariance) {
  std::mt19937 rng(9);
  std::normal_distribution<double> unit(0.0, 1.0);
  const Eigen::Isometry3d G = Eigen::Translation3d(3.0, -1.0, 0.8) * Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 1).normalized());
  std::vector<StampedPose> estimate, truth;
  std::vector<Eigen::Matrix<double, 6, 6>> covariances, claimed_less;
  for (int k = 0; k < 3000; ++k) {
    const Eigen::Isometry3d camera = Eigen::Translation3d(0.01 * k, std::sin(0.01 * k), 0.2) *
                                     Eigen::AngleAxisd(0.002 * k, Eigen::Vector3d::UnitY());
    truth.push_back({0.1 * k, G * camera});
    // Drift growing along the path: sigma per axis 1 mm + 1 mm per 100 poses.
    const double sigma = 0.001 * (1.0 + 0.01 * k), sigma_rotation = 0.0005 * (1.0 + 0.01 * k);
    Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
    if (k > 0) C.diagonal() << sigma * sigma, sigma * sigma, sigma * sigma, sigma_rotation * sigma_rotation,
        sigma_rotation * sigma_rotation, sigma_rotation * sigma_rotation;
    Eigen::Isometry3d drifted = camera;
    if (k > 0) {
      const Eigen::Vector3d dt(sigma * unit(rng), sigma * unit(rng), sigma * unit(rng));
      const Eigen::Vector3d dr(sigma_rotation * unit(rng), sigma_rotation * unit(rng), sigma_rotation * unit(rng));
      drifted.translation() += dt;
      drifted.linear() = Eigen::AngleAxisd(dr.norm(), dr.normalized()).toRotationMatrix() * camera.linear();
    }
    estimate.push_back({0.1 * k, drifted});
    covariances.push_back(C);
    claimed_less.push_back(C / 4.0);
  }
  const eval::AssociatedTrajectory associated = eval::associate(estimate, truth);
  ASSERT_EQ(associated.estimate_index.size(), estimate.size());
  EXPECT_EQ(associated.estimate_index[7], 7u);
  const eval::CovarianceConsistency c = eval::covarianceConsistency(associated, covariances);
  EXPECT_EQ(c.poses, 2999);
  EXPECT_NEAR(c.position_ratio, 1.0, 0.1);
  EXPECT_NEAR(c.rotation_ratio, 1.0, 0.1);
  EXPECT_GT(c.within_two_sigma, 0.98);  // |e|^2 / sigma^2 is chi-square(3): below 12 on 99.3 %
  const eval::CovarianceConsistency over = eval::covarianceConsistency(associated, claimed_less);
  EXPECT_NEAR(over.position_ratio, 4.0, 0.4);
  EXPECT_LT(over.within_two_sigma, 0.8);  // chi-square(3) below 3: 61 %
  EXPECT_THROW(eval::covarianceConsistency(associated, {covariances[0]}), InputError);
  EXPECT_THROW(eval::covarianceConsistency(eval::associate({estimate[0]}, truth), {covariances[0]}), InputError);
}


// Frame-to-frame motions drawn from the covariances they report (in the
// first frame's axes, turning 3° a frame), the truth in another world: the
// ratios are 1. Frames without ground truth leave their motions out.
TEST(MotionConsistency, IsOneForMotionsDrawnFromTheirCovariance) {
  std::mt19937 rng(10);
  std::normal_distribution<double> unit(0.0, 1.0);
  const Eigen::Isometry3d G = Eigen::Translation3d(-2.0, 0.5, 1.0) * Eigen::AngleAxisd(0.7, Eigen::Vector3d(2, 1, -1).normalized());
  std::vector<StampedPose> estimate, truth;
  for (int k = 0; k < 2001; ++k) {
    const Eigen::Isometry3d camera = Eigen::Translation3d(0.02 * k, 0.3 * std::cos(0.05 * k), 0.0) *
                                     Eigen::AngleAxisd(0.05 * k, Eigen::Vector3d(0.1, 1.0, 0.2).normalized());
    if (k % 100 != 50) truth.push_back({0.1 * k, G * camera});  // one frame in 100 without ground truth
    estimate.push_back({0.1 * k, camera});
  }
  Eigen::Matrix<double, 6, 1> sd;
  sd << 0.004, 0.0005, 0.002, 0.001, 0.0002, 0.003;
  std::vector<eval::FrameMotion> motions;
  for (size_t k = 1; k < estimate.size(); ++k) {
    eval::FrameMotion m;
    m.from = k - 1, m.to = k;
    m.covariance = sd.cwiseAbs2().asDiagonal();
    m.from_T_to = estimate[k - 1].world_T_camera.inverse() * estimate[k].world_T_camera;
    Eigen::Matrix<double, 6, 1> d;
    for (int i = 0; i < 6; ++i) d(i) = sd(i) * unit(rng);
    m.from_T_to.translation() += d.head<3>();
    m.from_T_to.linear() = Eigen::AngleAxisd(d.tail<3>().norm(), d.tail<3>().normalized()) * m.from_T_to.linear();
    motions.push_back(m);
  }
  const eval::AssociatedTrajectory associated = eval::associate(estimate, truth);
  const eval::CovarianceConsistency c = eval::motionConsistency(associated, motions);
  EXPECT_EQ(c.poses, 2000 - 2 * 20);
  EXPECT_NEAR(c.position_ratio, 1.0, 0.1);
  EXPECT_NEAR(c.rotation_ratio, 1.0, 0.1);
  for (eval::FrameMotion& m : motions) m.covariance /= 4.0;
  EXPECT_NEAR(eval::motionConsistency(associated, motions).position_ratio, 4.0, 0.4);
  EXPECT_EQ(eval::motionConsistency(associated, {}).poses, 0);
  EXPECT_EQ(eval::motionConsistency(associated, {motions[49]}).poses, 0);  // frame 50 has no ground truth
}

}  // namespace
}  // namespace risas

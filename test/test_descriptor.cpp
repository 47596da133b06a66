// Descriptor structure: dimensions, normalisation, dropped keypoints, the
// pieces of paper III-B on hand-checkable input.
#include "synthetic_fixtures.hpp"

#include "risas/detector.hpp"
#include "risas/encoding.hpp"
#include "risas/grey_noise.hpp"
#include "risas/neighbourhood.hpp"
#include "risas/orientation.hpp"
#include "risas/orientation_histogram.hpp"
#include "risas/ranking.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <numeric>

namespace risas {
namespace {

TEST(Scale, Equation3) {
  EXPECT_FLOAT_EQ(depthScale(0.5f), 1.0f);  // below 2 m: truncated to 1
  EXPECT_FLOAT_EQ(depthScale(2.0f), 1.0f);
  EXPECT_FLOAT_EQ(depthScale(5.0f), (3.8f - 2.0f) / 3.0f);
  EXPECT_FLOAT_EQ(depthScale(8.0f), 0.2f);
  EXPECT_FLOAT_EQ(depthScale(20.0f), 0.2f);
}

TEST(Scale, Equation4InitialRadius) {
  EXPECT_FLOAT_EQ(initialRadius(1.0f, 1.0f, 1.0f), 20.0f);     // the reference's 20 s
  EXPECT_FLOAT_EQ(initialRadius(0.5f, 0.5f, 1.0f), 22.5f);     // ratio 2 -> 45 s
  EXPECT_FLOAT_EQ(initialRadius(1.0f, 0.2f, 1.0f), 70.0f);     // ratio capped at 3
  EXPECT_FLOAT_EQ(initialRadius(1.0f, 0.05f, 1.0f), 70.0f);    // s floored at 0.2
}

TEST(Ranking, RankGroupsAreEqualSizedAndTiesShareAGroup) {
  std::vector<uint16_t> values;
  for (int i = 0; i < 100; ++i) values.push_back(static_cast<uint16_t>(99 - i));
  std::vector<uint8_t> labels;
  rankGroups(values, 256, 10, labels);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(labels[static_cast<size_t>(i)], (99 - i) / 10);
  rankGroups({5, 5, 5, 9}, 256, 4, labels);
  EXPECT_EQ(labels, (std::vector<uint8_t>{0, 0, 0, 3}));
  // A strictly monotonic transform of the values leaves every label as it was.
  std::vector<uint16_t> squared;
  for (uint16_t v : values) squared.push_back(static_cast<uint16_t>(v * v / 40 + v));
  std::vector<uint8_t> squared_labels;
  rankGroups(values, 256, 10, labels);
  rankGroups(squared, 512, 10, squared_labels);
  EXPECT_EQ(labels, squared_labels);
  EXPECT_THROW(rankGroups({300}, 256, 4, labels), cv::Exception);
}

TEST(Ranking, LevelsAboveTheLastCountedOneStayInTheLastGroup) {
  // Issue 20: levels past the highest counted one were labelled `groups`,
  // one past the last group, and the encoder indexed its histogram with it.
  int histogram[256] = {};
  histogram[10] = 3, histogram[20] = 1;
  uint8_t table[256];
  for (int groups : {1, 2, 4, 8, 256}) {
    rankGroupTable(histogram, 256, groups, table);
    for (int v = 0; v < 256; ++v) EXPECT_LT(table[v], groups) << "level " << v << ", " << groups << " groups";
  }
  rankGroupTable(histogram, 256, 4, table);
  EXPECT_EQ(table[10], 0);  // counted levels keep their groups: 0 of 4 below
  EXPECT_EQ(table[20], 3);  // 3 of 4 below
  const int empty[256] = {};
  rankGroupTable(empty, 256, 4, table);
  for (int v = 0; v < 256; ++v) EXPECT_EQ(table[v], 0);
}

TEST(Ranking, SoftRankPositionsSplitAVoteBetweenTheTwoNearestGroups) {
  // 8 values, one per level 0..7, in 4 groups of 2: mid-ranks 0.5 .. 7.5,
  // group centres at ranks 1, 3, 5 and 7. Level 2 (mid-rank 2.5) lies three
  // quarters of the way from group 0's centre to group 1's.
  int histogram[256] = {};
  for (int v = 0; v < 8; ++v) histogram[v] = 1;
  uint8_t lower[256];
  float upper[256];
  rankPositionTable(histogram, 256, 4, 0.0f, lower, upper);
  EXPECT_EQ(lower[0], 0);  // below the first centre: all in group 0
  EXPECT_FLOAT_EQ(upper[0], 0.0f);
  EXPECT_EQ(lower[1], 0);  // mid-rank 1.5: a quarter of the way to group 1
  EXPECT_FLOAT_EQ(upper[1], 0.25f);
  EXPECT_EQ(lower[2], 0);  // mid-rank 2.5: three quarters
  EXPECT_FLOAT_EQ(upper[2], 0.75f);
  EXPECT_EQ(lower[3], 1);  // mid-rank 3.5: a quarter past group 1's centre
  EXPECT_FLOAT_EQ(upper[3], 0.25f);
  EXPECT_EQ(lower[7], 3);  // past the last centre: all in group 3
  EXPECT_FLOAT_EQ(upper[7], 0.0f);
  for (int v = 8; v < 256; ++v) EXPECT_EQ(lower[v], 3) << v;  // above every value: the last group
  // Ties share one position, their run's middle: 4 values at level 10 and 4
  // at level 20 in 2 groups sit at the two centres.
  int ties[256] = {};
  ties[10] = 4, ties[20] = 4;
  rankPositionTable(ties, 256, 2, 0.0f, lower, upper);
  EXPECT_EQ(lower[10], 0);
  EXPECT_FLOAT_EQ(upper[10], 0.0f);
  EXPECT_EQ(lower[20], 1);
  EXPECT_FLOAT_EQ(upper[20], 0.0f);
  const int empty[256] = {};
  rankPositionTable(empty, 256, 4, 0.0f, lower, upper);
  for (int v = 0; v < 256; ++v) EXPECT_EQ(lower[v], 0);
}

// Under grey noise each counted level takes its expected mid-rank: the sum
// over the values of Phi(difference / (sqrt(2) noise)), a tie counting half.
TEST(Ranking, SoftRankPositionsUnderNoiseAreTheExpectedMidRanks) {
  int histogram[256] = {};
  cv::RNG rng(11);
  for (int i = 0; i < 400; ++i) ++histogram[90 + rng.uniform(0, 40)];  // a patch of low contrast
  histogram[30] = 25, histogram[220] = 25;                             // and two far levels
  const int groups = 4;
  const float noise = 3.0f;
  uint8_t lower[256];
  float upper[256];
  rankPositionTable(histogram, 256, groups, noise, lower, upper);
  const double s = std::sqrt(2.0) * noise;
  int checked = 0;
  for (int v = 0; v < 256; ++v) {
    if (!histogram[v]) continue;
    double expected = 0.0, total = 0.0;  // every value, Phi not cut off
    for (int w = 0; w < 256; ++w) {
      expected += histogram[w] * 0.5 * std::erfc(-(v - w) / (s * std::sqrt(2.0)));
      total += histogram[w];
    }
    const double position = std::clamp(expected * groups / total - 0.5, 0.0, groups - 1.0);
    EXPECT_NEAR(lower[v] + upper[v], position, 1e-3) << "level " << v;
    ++checked;
  }
  EXPECT_GT(checked, 30);
  // Levels further apart than the noise keep their exact positions: the far
  // ones here, and every level when the values lie far apart.
  uint8_t exact_lower[256];
  float exact_upper[256];
  rankPositionTable(histogram, 256, groups, 0.0f, exact_lower, exact_upper);
  for (const int v : {30, 220}) EXPECT_NEAR(lower[v] + upper[v], exact_lower[v] + exact_upper[v], 1e-4) << v;
  int spread[256] = {};
  for (int v = 10; v < 256; v += 40) spread[v] = 3 + v % 7;
  rankPositionTable(spread, 256, groups, noise, lower, upper);
  rankPositionTable(spread, 256, groups, 0.0f, exact_lower, exact_upper);
  for (int v = 10; v < 256; v += 40) {
    EXPECT_EQ(lower[v], exact_lower[v]) << v;
    EXPECT_NEAR(upper[v], exact_upper[v], 1e-4) << v;
  }
  // Two levels one grey level apart, half the values each: exactly ranked
  // they lie at the two groups' centres; under noise of ten levels both lie
  // near the middle (0.47 and 0.53), one vote split almost evenly.
  int two[256] = {};
  two[100] = 50, two[101] = 50;
  rankPositionTable(two, 256, 2, 0.0f, lower, upper);
  EXPECT_FLOAT_EQ(lower[100] + upper[100], 0.0f);
  EXPECT_FLOAT_EQ(lower[101] + upper[101], 1.0f);
  rankPositionTable(two, 256, 2, 10.0f, lower, upper);
  EXPECT_NEAR(lower[100] + upper[100], 0.5f, 0.04f);
  EXPECT_NEAR(lower[101] + upper[101], 0.5f, 0.04f);
  EXPECT_LT(lower[100] + upper[100], lower[101] + upper[101]);  // the order kept, as far as it is sure
}

// Immerkaer's estimator: the noise's sigma on a planar image, and 0 without
// noise or without a pixel the mask fits around.
TEST(GreyNoise, EstimatesTheSigmaOfGaussianNoise) {
  cv::Mat ramp(240, 320, CV_8UC1);
  for (int y = 0; y < ramp.rows; ++y) {
    for (int x = 0; x < ramp.cols; ++x) ramp.at<uchar>(y, x) = static_cast<uchar>(20 + x / 2 + y / 3);
  }
  EXPECT_LT(estimateGreyNoise(cv::Mat(240, 320, CV_8UC1, cv::Scalar(128))), 1e-12);
  EXPECT_LT(estimateGreyNoise(ramp), 0.8);  // a plane of grey, but for the levels' rounding
  for (const double sigma : {2.0, 5.0, 12.0}) {
    cv::Mat noise(ramp.size(), CV_32F), noisy;
    cv::RNG(5).fill(noise, cv::RNG::NORMAL, 0.0, sigma);
    ramp.convertTo(noisy, CV_32F);
    noisy += noise;
    noisy.convertTo(noisy, CV_8U);
    EXPECT_NEAR(estimateGreyNoise(noisy), sigma, 0.06 * sigma + 0.2) << sigma;
  }
  EXPECT_EQ(estimateGreyNoise(cv::Mat(2, 9, CV_8UC1, cv::Scalar(3))), 0.0);  // no pixel the mask fits around
  EXPECT_EQ(estimateGreyNoise(cv::Mat()), 0.0);
}

TEST(Neighbourhood, KeepsTheForegroundOfTheDiscAndItsMoments) {
  // A plane at 1 m with a step to 1.5 m at column 9 and a grey ramp rising
  // to the right in steps of 3 columns (ties). Discs of radius 8.5 about
  // (5, 20) and (34, 20) are cut by the left and the right edge; eq. 5 keeps
  // their pixels on the keypoint's side of the step (within t = 0.2 m of
  // k_i: 8.5 px at fx = 100 are 0.085 m at 1 m and 0.1275 m at 1.5 m), in
  // rows of every length.
  const int width = 40, height = 40, step_column = 9;
  const float radius = 8.5f;
  cv::Mat depth(height, width, CV_32FC1, cv::Scalar(1.0f)), gray(height, width, CV_8UC1);
  depth.colRange(step_column, width).setTo(1.5f);
  for (int u = 0; u < width; ++u) gray.col(u).setTo(5 * (u / 3));
  const Intrinsics K(100, 100, 20, 20);
  const RgbdFrame frame(gray, depth, K);
  const FrameGeometry g = computeGeometry(frame, GeometryParams());
  for (const cv::Point centre : {cv::Point(5, 20), cv::Point(34, 20)}) {
    SCOPED_TRACE(centre);
    const int u0 = centre.x, v0 = centre.y;
    const auto nb = selectNeighbourhood(frame, g, cv::Point2f(u0, v0), radius, 0.2);
    ASSERT_TRUE(nb.has_value());

    // The same by hand: the disc's pixels (du^2 + dv^2 <= 72 < 8.5^2) in the
    // image and on the keypoint's side of the step, their points about k_i
    // in double, and the middle rank of each pixel's grey level.
    const cv::Vec3f k = g.point(v0, u0);
    std::vector<cv::Point> pixels;
    int count[256] = {};
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
    for (int v = 0; v < height; ++v) {
      for (int u = 0; u < width; ++u) {
        if ((u - u0) * (u - u0) + (v - v0) * (v - v0) > 72 || (u < step_column) != (u0 < step_column)) continue;
        const cv::Vec3f p = g.point(v, u) - k;
        const Eigen::Vector3d d(p[0], p[1], p[2]);
        pixels.push_back({u, v});
        ++count[gray.at<uchar>(v, u)];
        sum += d;
        spread += d * d.transpose();
      }
    }
    const int kept = static_cast<int>(pixels.size());
    EXPECT_EQ(nb->kept, kept);
    EXPECT_LT((nb->centroid - (Eigen::Vector3d(k[0], k[1], k[2]) + sum / kept)).norm(), 1e-6);
    EXPECT_LT((nb->spread - spread / kept).norm(), 1e-7);
    Eigen::Vector2d intensity_centroid = Eigen::Vector2d::Zero();
    for (const cv::Point& q : pixels) {
      const int level = gray.at<uchar>(q);
      const double mid_rank = std::accumulate(count, count + level, 0) + 0.5 * (count[level] - 1);
      intensity_centroid += (mid_rank - 0.5 * (kept - 1)) * Eigen::Vector2d(q.x - u0, q.y - v0);
    }
    EXPECT_EQ(nb->intensity_centroid, intensity_centroid);
    // Brighter to the right, symmetric about row v0: it points along +u.
    EXPECT_GT(nb->intensity_centroid.x(), 0.0);
    EXPECT_EQ(nb->intensity_centroid.y(), 0.0);

    // Without the centroid: the same moments to the bit, the centroid zero.
    const auto without = selectNeighbourhood(frame, g, cv::Point2f(u0, v0), radius, 0.2, false);
    ASSERT_TRUE(without.has_value());
    EXPECT_EQ(without->kept, nb->kept);
    EXPECT_EQ(without->centroid, nb->centroid);
    EXPECT_EQ(without->covariance, nb->covariance);
    EXPECT_EQ(without->spread, nb->spread);
    EXPECT_EQ(without->intensity_centroid, Eigen::Vector2d::Zero());
  }
}

// The centroid is left out only where the gradients decide theta.
TEST(Neighbourhood, IntensityCentroidIsNeededWhereThetaCanComeFromIt) {
  DescriptorParams p;
  p.shape_orientation = false, p.gradient_orientation = true;
  EXPECT_FALSE(intensityCentroidNeeded(p));
  p.gradient_orientation = false;
  EXPECT_TRUE(intensityCentroidNeeded(p));
  p.shape_orientation = true;  // the fallback near the ray, and an eigenvector's sign
  EXPECT_TRUE(intensityCentroidNeeded(p));
  p.gradient_orientation = true;
  EXPECT_TRUE(intensityCentroidNeeded(p));
}

// The grey pyramid's levels read the same point of the image: on a ramp
// (which the pyramid's Gaussian keeps, away from the borders) greyAt gives
// the ramp's value at any level, whole or fractional, up to the 8-bit
// rounding of each level. And sampleLevel is the level whose blur is
// sample_blur sample spacings: spacing 2 px at 0.5 gives sigma 1, level 1.
TEST(Encoding, GreyPyramidLevelsReadTheSamePointAtEveryScale) {
  cv::Mat ramp(240, 320, CV_8UC1);
  const auto value = [](float x, float y) { return 20.0f + 0.4f * x + 0.1f * y; };
  for (int v = 0; v < ramp.rows; ++v) {
    for (int u = 0; u < ramp.cols; ++u) ramp.at<uchar>(v, u) = cv::saturate_cast<uchar>(value(u, v));
  }
  GreyPyramid pyramid;
  buildGreyPyramid(ramp, GreyPyramid::kMaxLevels, pyramid);
  ASSERT_EQ(pyramid.levels, GreyPyramid::kMaxLevels);
  EXPECT_EQ(pyramid.level[3].size(), cv::Size(40, 30));
  for (const float lambda : {0.0f, 0.5f, 1.0f, 1.7f, 2.0f, 2.4f, 3.0f}) {
    for (const cv::Point2f p : {cv::Point2f(100.3f, 80.6f), cv::Point2f(201.0f, 150.0f), cv::Point2f(64.5f, 120.25f)}) {
      EXPECT_NEAR(greyAt(pyramid, lambda, p.x, p.y), value(p.x, p.y), 1.0f) << "level " << lambda << " at " << p;
    }
  }
  DescriptorParams params;  // patch_radius 14
  params.sample_blur = 0.5;
  EXPECT_FLOAT_EQ(sampleLevel(28.0f, params, 4), 1.0f);
  EXPECT_FLOAT_EQ(sampleLevel(28.0f, params, 1), 0.0f);  // no coarser level to read
  EXPECT_LT(sampleLevel(10.0f, params, 4), 0.5f);
  params.sample_blur = 0.0;
  EXPECT_EQ(sampleLevel(50.0f, params, 4), 0.0f);
  params.gradient_orientation = false;
  EXPECT_EQ(pyramidLevelsNeeded(params), 1);
  // The gradient orientation reads at 1.5 sample spacings: the widest patch,
  // 50 px, 3.6 px spacing, blur 5.4 px, level 3.2: all four levels.
  params.gradient_orientation = true;
  EXPECT_FLOAT_EQ(blurLevel(kOrientationBlur * 50.0 / 14, 8), 0.5f * std::log2(1.0f + 3.0f * std::pow(1.5f * 50 / 14, 2.0f)));
  EXPECT_EQ(pyramidLevelsNeeded(params), 4);
  // A level under 2 x 2 pixels is not made.
  buildGreyPyramid(cv::Mat(5, 9, CV_8UC1, cv::Scalar(7)), GreyPyramid::kMaxLevels, pyramid);
  EXPECT_EQ(pyramid.levels, 2);
  EXPECT_EQ(greyAt(pyramid, 1.0f, 8.0f, 4.0f), 7.0f);
}

TEST(Descriptor, DimensionIsNRingTimesNPieTimesNBinTimesNVecPlusOne) {
  const RgbdFrame frame = test::renderFrame(SyntheticScene::demo(), test::demoCamera());
  EXPECT_EQ(Risas().descriptorSize(), 64);  // 2 rings x 8 sectors x 4 rank groups, as the paper's 8 x 8 without shape labels
  for (const cv::Vec4i& bins : {cv::Vec4i(1, 8, 8, 0), cv::Vec4i(1, 8, 8, 2), cv::Vec4i(2, 8, 4, 0), cv::Vec4i(1, 4, 8, 1),
                                cv::Vec4i(3, 12, 16, 2), cv::Vec4i(2, 3, 5, 4)}) {
    RisasParams params;
    params.descriptor.n_ring = bins[0];
    params.descriptor.n_pie = bins[1];
    params.descriptor.n_bin = bins[2];
    params.descriptor.n_vec = bins[3];
    const auto risas = Risas::create(params);
    const Features f = risas->extract(frame);
    ASSERT_GT(f.keypoints.size(), 100u);
    EXPECT_EQ(f.descriptors.cols, bins[0] * bins[1] * bins[2] * (bins[3] + 1));
    EXPECT_EQ(risas->descriptorSize(), f.descriptors.cols);
    EXPECT_EQ(f.descriptors.type(), CV_32F);
    EXPECT_EQ(f.descriptors.rows, static_cast<int>(f.keypoints.size()));
    EXPECT_EQ(f.geometry.size(), f.keypoints.size());
    for (int r = 0; r < f.descriptors.rows; ++r) EXPECT_NEAR(cv::norm(f.descriptors.row(r)), 1.0, 1e-4);
  }
}

TEST(Descriptor, RingsSplitEachSectorsHistogramInTwoHalvesOfTheDisc) {
  // With n_ring = 2 each (sector, rank, shape) count is split between an
  // inner and an outer ring of about equal area: the two halves add up to
  // the one-ring histogram of the same keypoints (before normalisation).
  const RgbdFrame frame = test::renderFrame(SyntheticScene::demo(), test::demoCamera());
  RisasParams one, two;
  one.descriptor.n_ring = 1;
  two.descriptor.n_ring = 2;
  std::vector<cv::KeyPoint> keypoints;
  Risas(one).detect(frame, keypoints);
  std::vector<cv::KeyPoint> k1 = keypoints, k2 = keypoints;
  cv::Mat d1, d2;
  Risas(one).compute(frame, k1, d1);
  Risas(two).compute(frame, k2, d2);
  ASSERT_EQ(d2.cols, 2 * d1.cols);
  ASSERT_EQ(d1.rows, d2.rows);
  ASSERT_GT(d1.rows, 100);
  double inner_mass = 0.0, outer_mass = 0.0;
  for (int r = 0; r < d1.rows; ++r) {
    cv::Mat sum = d2.row(r).colRange(0, d1.cols) + d2.row(r).colRange(d1.cols, d2.cols);
    sum /= cv::norm(sum);
    EXPECT_LT(cv::norm(sum, d1.row(r), cv::NORM_INF), 1e-5) << "keypoint " << r;
    inner_mass += cv::sum(d2.row(r).colRange(0, d1.cols))[0];
    outer_mass += cv::sum(d2.row(r).colRange(d1.cols, d2.cols))[0];
  }
  EXPECT_NEAR(inner_mass / outer_mass, 1.0, 0.15);  // about equal areas, mostly counted
}

TEST(Descriptor, SetsAngleSizeAndGeometryConsistentWithDepth) {
  SyntheticRender render;
  const RgbdFrame frame = test::renderFrame(SyntheticScene::demo(), test::demoCamera(), &render);
  const Features f = Risas().extract(frame);
  ASSERT_GT(f.keypoints.size(), 100u);
  const Intrinsics K = syntheticIntrinsics();
  for (size_t i = 0; i < f.keypoints.size(); ++i) {
    const cv::KeyPoint& k = f.keypoints[i];
    const KeypointGeometry& g = f.geometry[i];
    EXPECT_GE(k.angle, 0.0f);
    EXPECT_LT(k.angle, 360.0f);
    EXPECT_GE(k.size, 2.0f * RisasParams().descriptor.min_radius_px - 1e-3f);
    EXPECT_NEAR(g.point.z, render.depth_mm.at<uint16_t>(cvRound(k.pt.y), cvRound(k.pt.x)) / 1000.0, 1e-3);
    const cv::Point2f back = K.project(g.point);
    EXPECT_LT(cv::norm(back - k.pt), 1.0);
    EXPECT_NEAR(cv::norm(g.normal), 1.0, 1e-4);
    EXPECT_LT(g.normal.dot(cv::Vec3f(g.point.x, g.point.y, g.point.z)), 0.0f);
    EXPECT_GT(g.support_radius, 0.0f);
  }
}

TEST(Descriptor, DropsKeypointsItCannotDescribe) {
  SyntheticRender render;
  const RgbdFrame frame = test::renderFrame(SyntheticScene::demo(), test::demoCamera(), &render);
  const Risas risas;
  // A keypoint that was described, far enough from the hole cut below.
  const std::vector<cv::KeyPoint> keypoints = risas.extract(frame).keypoints;
  const auto good_it = std::find_if(keypoints.begin(), keypoints.end(), [](const cv::KeyPoint& k) {
    return !cv::Rect(200, 100, 240, 240).contains(k.pt);
  });
  ASSERT_NE(good_it, keypoints.end());
  const cv::KeyPoint good = *good_it;
  // Off the image on either side, and on a pixel whose depth is missing.
  cv::Mat depth = render.depth_mm.clone();
  depth(cv::Rect(300, 200, 40, 40)).setTo(0);
  const RgbdFrame holed(render.bgr, depth, syntheticIntrinsics());
  std::vector<cv::KeyPoint> mixed = {cv::KeyPoint(-5.0f, 10.0f, 7.0f), good, cv::KeyPoint(700.0f, 10.0f, 7.0f),
                                     cv::KeyPoint(320.0f, 220.0f, 7.0f)};
  cv::Mat descriptors;
  std::vector<KeypointGeometry> info;
  risas.compute(holed, mixed, descriptors, &info);
  ASSERT_EQ(mixed.size(), 1u);
  EXPECT_EQ(mixed[0].pt, good.pt);
  EXPECT_EQ(descriptors.rows, 1);
  EXPECT_EQ(info.size(), 1u);
}

// f() on the kernels' path, then on the readable one
// (cv::setUseOptimized(false)).
template <class F>
auto onBothPaths(F f) {
  const auto fast = f();
  cv::setUseOptimized(false);
  const auto readable = f();
  cv::setUseOptimized(true);
  return std::make_pair(fast, readable);
}

// The demo scene, its geometry and the detector's `count` strongest
// keypoints on it: the kernels' tests compare their paths on these.
struct DemoKeypoints {
  explicit DemoKeypoints(size_t count)
      : frame(test::renderFrame(SyntheticScene::demo(), test::demoCamera())),
        geometry(computeGeometry(frame, GeometryParams())) {
    Detector().detect(frame, geometry, keypoints);
    EXPECT_GE(keypoints.size(), count);
    keypoints.resize(std::min(count, keypoints.size()));
  }
  // The grey pyramid the descriptor reads with params.
  GreyPyramid pyramid(const DescriptorParams& params) const {
    GreyPyramid grey;
    buildGreyPyramid(frame.gray(), pyramidLevelsNeeded(params), grey);
    return grey;
  }
  // The foreground about `keypoint` in a disc of 30 px.
  std::optional<Neighbourhood> neighbourhood(const cv::KeyPoint& keypoint, const DescriptorParams& params) const {
    return selectNeighbourhood(frame, geometry, keypoint.pt, 30.0f, params.background_distance);
  }
  RgbdFrame frame;
  FrameGeometry geometry;
  std::vector<cv::KeyPoint> keypoints;
};

TEST(Descriptor, EncodingIsThePapersHistogramOnEveryPath) {
  // The kernel (kernels/patch_encoding.cpp) against the readable encoding
  // (encoding.cpp, cv::setUseOptimized(false)): keypoints of the demo scene
  // (texture and curved, tilted surfaces), at several angles and radii (so
  // at whole and fractional pyramid levels), one reaching past the image's
  // edge; one vote or soft binning, the frame's grey image or the pyramid,
  // without the shape labels, with them in the joint histogram (the
  // paper's) and in a histogram of their own (shape_weight); soft binning's
  // ranks exact (the frame's grey image) and under grey noise of four levels
  // (the pyramid).
  const DemoKeypoints demo(20);
  const FrameGeometry& g = demo.geometry;
  std::vector<cv::KeyPoint> keypoints = demo.keypoints;
  keypoints.emplace_back(cv::Point2f(4.0f, 240.0f), 7.0f);  // the disc crosses the left edge
  keypoints.emplace_back(cv::Point2f(637.0f, 478.0f), 7.0f);  // past the coarse levels' last pixel
  for (const auto& [n_vec, shape_weight] : {std::pair{0, 0.0}, std::pair{2, 0.0}, std::pair{2, 0.5}}) {
  for (const bool soft_binning : {false, true}) {
    for (const double sample_blur : {0.0, 0.5, 1.5}) {
      SCOPED_TRACE(std::string(soft_binning ? "soft binning" : "one vote per sample") + ", sample_blur " +
                   std::to_string(sample_blur) + ", n_vec " + std::to_string(n_vec) + ", shape_weight " +
                   std::to_string(shape_weight));
      DescriptorParams params;
      params.n_vec = n_vec;
      params.shape_weight = shape_weight;
      params.soft_binning = soft_binning;
      params.sample_blur = sample_blur;
      const PatchEncoder encoder(params);
      GreyPyramid grey = demo.pyramid(params);
      grey.noise = soft_binning && sample_blur > 0.0 ? 4.0f : 0.0f;
      int compared = 0, fractional = 0;
      for (size_t i = 0; i < keypoints.size(); ++i) {
        const auto nb = demo.neighbourhood(keypoints[i], params);
        if (!nb) continue;
        const float radius = 8.0f + 2.0f * static_cast<float>(i);
        const double theta = 0.37 * static_cast<double>(i) - 2.0;
        const auto [fast, readable] = onBothPaths([&] {
          std::vector<float> histogram(static_cast<size_t>(encoder.dimension()));
          if (!encoder.encode(grey, g, *nb, radius, theta, histogram.data())) histogram.clear();
          return histogram;
        });
        ASSERT_EQ(fast.empty(), readable.empty()) << i;
        if (fast.empty()) continue;
        ++compared;
        const float lambda = sampleLevel(radius, params, grey.levels);
        fractional += lambda != std::floor(lambda);
        for (size_t d = 0; d < fast.size(); ++d) ASSERT_NEAR(fast[d], readable[d], 1e-6f) << i << ": bin " << d;
      }
      EXPECT_GE(compared, 12);
      if (sample_blur > 0.0) {
        EXPECT_GE(fractional, 10);
      }
    }
  }
  }
}

// shape_weight's two histograms are the joint histogram's two marginals:
// summed over the shape labels, eq. 8's histogram is the intensity part;
// summed over the intensity groups (a sample's votes there add to one, soft
// binning or not), the shape part. Each part keeps its share of the unit
// length: 1 and shape_weight, over sqrt(1 + shape_weight^2).
TEST(Descriptor, OwnShapeHistogramIsTheJointHistogramsMarginal) {
  const DemoKeypoints demo(20);
  for (const bool soft_binning : {false, true}) {
    SCOPED_TRACE(soft_binning ? "soft binning" : "one vote per sample");
    DescriptorParams joint;
    joint.n_vec = 2;
    joint.soft_binning = soft_binning;
    DescriptorParams own = joint;
    own.shape_weight = 0.5;
    const int sectors = joint.n_ring * joint.n_pie, groups = joint.n_bin, shapes = joint.n_vec + 1;
    ASSERT_EQ(own.dimension(), sectors * (groups + shapes));
    const GreyPyramid grey = demo.pyramid(joint);
    int compared = 0;
    for (size_t i = 0; i < demo.keypoints.size(); ++i) {
      const auto nb = demo.neighbourhood(demo.keypoints[i], joint);
      if (!nb) continue;
      std::vector<float> j(static_cast<size_t>(joint.dimension())), o(static_cast<size_t>(own.dimension()));
      const double theta = 0.37 * static_cast<double>(i);
      ASSERT_EQ(PatchEncoder(joint).encode(grey, demo.geometry, *nb, 12.0f, theta, j.data()),
                PatchEncoder(own).encode(grey, demo.geometry, *nb, 12.0f, theta, o.data()));
      if (cv::norm(j) == 0.0) continue;  // not described
      ++compared;
      std::vector<float> over_shapes(static_cast<size_t>(sectors * groups), 0.0f);
      std::vector<float> over_groups(static_cast<size_t>(sectors * shapes), 0.0f);
      for (int sector = 0; sector < sectors; ++sector) {
        for (int group = 0; group < groups; ++group) {
          for (int shape = 0; shape < shapes; ++shape) {
            const float bin = j[static_cast<size_t>((sector * groups + group) * shapes + shape)];
            over_shapes[static_cast<size_t>(sector * groups + group)] += bin;
            over_groups[static_cast<size_t>(sector * shapes + shape)] += bin;
          }
        }
      }
      const auto shape_begin = o.begin() + sectors * groups;
      const std::vector<float> intensity(o.begin(), shape_begin), shape(shape_begin, o.end());
      const double length = std::sqrt(1.0 + own.shape_weight * own.shape_weight);
      EXPECT_NEAR(cv::norm(intensity), 1.0 / length, 1e-6) << i;
      EXPECT_NEAR(cv::norm(shape), own.shape_weight / length, 1e-6) << i;
      const auto unit = [](std::vector<float> v) {
        cv::normalize(v, v);
        return v;
      };
      EXPECT_LT(cv::norm(unit(intensity), unit(over_shapes), cv::NORM_INF), 1e-6) << i;
      EXPECT_LT(cv::norm(unit(shape), unit(over_groups), cv::NORM_INF), 1e-6) << i;
    }
    EXPECT_GE(compared, 12);
  }
}

// The frame's grey image with Gaussian noise of `sigma` grey levels (seeded)
// added, as a camera's gain adds it in dim light.
RgbdFrame withGreyNoise(const RgbdFrame& frame, double sigma, uint64_t seed) {
  cv::Mat noise(frame.size(), CV_32F), grey;
  cv::RNG(seed).fill(noise, cv::RNG::NORMAL, 0.0, sigma);
  frame.gray().convertTo(grey, CV_32F);
  grey += noise;
  grey.convertTo(grey, CV_8U);
  return RgbdFrame(grey, frame.depth(), frame.intrinsics());
}

// Why descriptor.soft_binning is the default: described 1.5 px off, in a
// frame with sensor noise (grey sigma 2), a keypoint's descriptor passes the
// ratio test against its own undisturbed descriptor more often when samples
// split their votes between rank groups; with one vote per sample, samples
// near a group boundary move whole votes.
double shareMatchedToItself(const RisasParams& params, const RgbdFrame& frame, const RgbdFrame& disturbed,
                            cv::Point2f shift) {
  const Risas risas(params);
  std::vector<cv::KeyPoint> reference;
  risas.detect(frame, reference);
  const size_t detected = reference.size();
  for (size_t i = 0; i < detected; ++i) reference[i].class_id = static_cast<int>(i);
  std::vector<cv::KeyPoint> moved = reference;
  for (cv::KeyPoint& k : moved) k.pt += shift;
  cv::Mat reference_descriptors, moved_descriptors;
  risas.compute(frame, reference, reference_descriptors);
  risas.compute(disturbed, moved, moved_descriptors);
  std::vector<int> row_of(detected, -1);  // by class_id: the index before compute dropped any
  for (size_t r = 0; r < reference.size(); ++r) row_of[static_cast<size_t>(reference[r].class_id)] = static_cast<int>(r);
  int compared = 0, matched = 0;
  for (int m = 0; m < moved_descriptors.rows; ++m) {
    const int own = row_of[static_cast<size_t>(moved[static_cast<size_t>(m)].class_id)];
    if (own < 0) continue;
    double nearest_other = std::numeric_limits<double>::infinity();
    for (int r = 0; r < reference_descriptors.rows; ++r) {
      if (r != own) nearest_other = std::min(nearest_other, cv::norm(moved_descriptors.row(m), reference_descriptors.row(r)));
    }
    ++compared;
    matched += cv::norm(moved_descriptors.row(m), reference_descriptors.row(own)) < 0.8 * nearest_other;
  }
  EXPECT_GT(compared, 100);
  return compared ? static_cast<double>(matched) / compared : 0.0;
}

// The demo scene described, and again in a copy with grey noise (sigma 2,
// a fixed seed) with every keypoint shifted by (1.5, 0) px and by (-1, 1) px:
// at each shift `better` keeps more of the keypoints nearest their own
// undisturbed descriptor than `base` does, by more than `margin`.
void expectMoreMatchedToThemselves(const RisasParams& base, const RisasParams& better, double margin) {
  const RgbdFrame frame = test::renderFrame(SyntheticScene::demo(), test::demoCamera());
  const RgbdFrame noisy = withGreyNoise(frame, 2.0, 7);
  for (const cv::Point2f shift : {cv::Point2f(1.5f, 0.0f), cv::Point2f(-1.0f, 1.0f)}) {
    const double base_share = shareMatchedToItself(base, frame, noisy, shift);
    const double better_share = shareMatchedToItself(better, frame, noisy, shift);
    EXPECT_GT(better_share, base_share + margin) << "shift " << shift;
  }
}

TEST(Descriptor, SoftBinningKeepsAShiftedNoisyKeypointNearestItself) {
  // Samples read the frame's own grey image: the pyramid's blur (sample_blur)
  // damps the same noise, and would hide what the binning does.
  RisasParams hard, soft;
  hard.descriptor.soft_binning = false;
  soft.descriptor.soft_binning = true;
  hard.descriptor.sample_blur = soft.descriptor.sample_blur = 0.0;
  expectMoreMatchedToThemselves(hard, soft, 0.1);
}

// Why descriptor.sample_blur is on: the same shifted, noisy keypoints, their
// samples read from the grey pyramid at half their spacing's blur. Grey noise
// and a sub-pixel shift move the raw image's samples; the blurred ones move
// less. Measured (soft binning, exact ranks, the two shifts): 0.67-0.69
// without, 0.73-0.75 with it (0.40 and 0.51 with one ring of eight rank
// groups). With ranks that allow for the frame's noise (grey_noise, the
// default) the blur gains less here (0.72 and 0.72 without, 0.76 and 0.73
// with it): both keep the noise from reordering the samples. The blur is
// there for the patches' scale too ("Samples read at their own scale").
TEST(Descriptor, SampleBlurKeepsAShiftedNoisyKeypointNearestItself) {
  RisasParams raw, blurred;
  raw.descriptor.sample_blur = 0.0;
  blurred.descriptor.sample_blur = 0.5;
  raw.descriptor.grey_noise = blurred.descriptor.grey_noise = 0.0;
  expectMoreMatchedToThemselves(raw, blurred, 0.05);
}

// The demo scene's texture at a quarter of its contrast with Kinect-like
// depth and grey noise of one level (and `added_noise` grey levels more,
// as dim light adds them), seen from one camera and from 10 and 20 degrees
// around the scene, two noise draws each: of B's keypoints re-detected at
// the same 3D point in A (counterparts), how many each setting matches to
// its own counterpart. The two settings detect alike.
struct MatchedToThemselves {
  int first = 0, second = 0, counterparts = 0;
};

MatchedToThemselves matchedAtLowContrast(const Risas& first, const Risas& second, double added_noise) {
  const SyntheticScene scene = SyntheticScene::demo();
  const Eigen::Vector3d target(0.0, 0.05, 0.15);
  const Eigen::Isometry3d camera_a = test::demoCamera(1.2);
  const auto view = [&](const Eigen::Isometry3d& camera, uint64_t seed) {
    const RgbdFrame frame = test::kinectLikeFrame(scene, camera, seed, 0.25);
    return added_noise > 0.0 ? withGreyNoise(frame, added_noise, seed + 10) : frame;
  };
  MatchedToThemselves matched;
  for (const double degrees : {10.0, 20.0}) {
    const Eigen::Isometry3d camera_b = lookAt(
        target + Eigen::AngleAxisd(degrees * CV_PI / 180.0, Eigen::Vector3d::UnitZ()) * (camera_a.translation() - target),
        target);
    for (const uint64_t seed : {3, 5}) {
      const RgbdFrame a = view(camera_a, seed), b = view(camera_b, seed + 1);
      const Eigen::Isometry3d a_T_b = camera_a.inverse() * camera_b;
      const test::CorrespondenceScore with_first = test::scoreCorrespondences(first.extract(a), first.extract(b), a_T_b);
      const test::CorrespondenceScore with_second =
          test::scoreCorrespondences(second.extract(a), second.extract(b), a_T_b);
      EXPECT_EQ(with_first.counterparts, with_second.counterparts);  // the same keypoints
      matched.first += with_first.matched, matched.second += with_second.matched;
      matched.counterparts += with_first.counterparts;
    }
  }
  return matched;
}

// Why the defaults cut the disc into two rings of four rank groups rather
// than the paper's one ring of eight (the same 64 dimensions): on a patch
// of low contrast the order of close grey levels is the sensor's noise, and
// finer groups move a point's votes from one view to the other, while the
// second ring keeps where the patch's parts lie. The demo scene's texture
// at a quarter of its contrast, grey noise of one level and Kinect-like
// depth, the camera 10 and 20 degrees around the scene. Measured with
// exact ranks: 601 against 511 of 906 counterparts matched to themselves
// (four groups in one ring: 546; two rings of eight: 551); at full
// contrast 728 against 671, at a tenth 362 against 300. With ranks that
// allow for the frame's noise (grey_noise, the default) 624 against 602:
// the coarser groups and the noise's allowance both keep close grey levels
// from moving votes.
TEST(Descriptor, TwoRingsOfFourRankGroupsMatchMoreOnALowContrastTexture) {
  RisasParams defaults_layout, papers_layout;
  defaults_layout.descriptor.grey_noise = papers_layout.descriptor.grey_noise = 0.0;
  papers_layout.descriptor.n_ring = 1, papers_layout.descriptor.n_bin = 8;
  const Risas defaults(defaults_layout), paper(papers_layout);
  ASSERT_EQ(defaults.descriptorSize(), paper.descriptorSize());
  const MatchedToThemselves matched = matchedAtLowContrast(defaults, paper, 0.0);
  EXPECT_GT(matched.counterparts, 600);
  EXPECT_GT(matched.first, 1.06 * matched.second) << matched.first << " against " << matched.second;
}

// grey_noise < 0 takes each frame's own noise as estimateGreyNoise reads it:
// the same descriptors as that estimate given as the parameter, and other
// ones than exact ranks.
TEST(Descriptor, GreyNoiseBelowZeroIsTheFramesEstimatedNoise) {
  const RgbdFrame frame = withGreyNoise(test::renderFrame(SyntheticScene::demo(), test::demoCamera()), 4.0, 3);
  const double estimate = estimateGreyNoise(frame.gray());
  EXPECT_NEAR(estimate, 4.0, 1.5);  // the demo's texture reads a little over the noise
  RisasParams estimated, given, exact;
  estimated.descriptor.grey_noise = -1.0;
  given.descriptor.grey_noise = static_cast<float>(estimate);  // as the descriptor holds it
  exact.descriptor.grey_noise = 0.0;
  std::vector<cv::KeyPoint> keypoints;
  Risas(estimated).detect(frame, keypoints);
  ASSERT_GT(keypoints.size(), 50u);
  const auto describe = [&](const RisasParams& params) {
    std::vector<cv::KeyPoint> described = keypoints;
    cv::Mat descriptors;
    Risas(params).compute(frame, described, descriptors);
    return descriptors;
  };
  const cv::Mat with_estimate = describe(estimated);
  ASSERT_EQ(with_estimate.size(), describe(given).size());
  EXPECT_EQ(cv::norm(with_estimate, describe(given), cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(with_estimate, describe(exact), cv::NORM_INF), 0.05);
}

// Why the ranks allow for the frame's noise by default: the scene's texture
// at a quarter of its contrast seen from two views 10 and 20 degrees apart,
// under grey noise as dim light adds it (sigma 6 on top of the Kinect-like
// frame's 1), where exact ranks reorder the patches' close grey levels from
// one view to the other. The same keypoints; more of them matched to their
// own counterparts with the noise allowed for. Measured: 449 against 380
// of 781.
TEST(Descriptor, RanksThatAllowForTheNoiseMatchMoreInDimLight) {
  RisasParams exact_ranks;
  exact_ranks.descriptor.grey_noise = 0.0;
  const MatchedToThemselves matched = matchedAtLowContrast(Risas(), Risas(exact_ranks), 6.0);
  EXPECT_GT(matched.counterparts, 300);
  EXPECT_GT(matched.first, 1.1 * matched.second) << matched.first << " against " << matched.second;
}

TEST(Descriptor, IsDeterministicAndReentrant) {
  const RgbdFrame frame = test::renderFrame(SyntheticScene::demo(), test::demoCamera());
  const auto risas = Risas::create();
  const Features a = risas->extract(frame);
  Features b, c;
  cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& r) {
    for (int i = r.start; i < r.end; ++i) (i == 0 ? b : c) = risas->extract(frame);
  });
  for (const Features* other : {&b, &c}) {
    ASSERT_EQ(other->keypoints.size(), a.keypoints.size());
    EXPECT_EQ(cv::norm(other->descriptors, a.descriptors, cv::NORM_INF), 0.0);
  }
}

TEST(Orientation, GammaRuleRejectsShapelessAndPicksTheBranches) {
  DescriptorParams paper;
  paper.shape_orientation = true;
  Neighbourhood nb;
  nb.point = Eigen::Vector3d(0.1, 0.05, 1.0);
  nb.intensity_centroid = Eigen::Vector2d(1.0, 0.0);
  const Intrinsics K(500, 500, 320, 240);
  nb.covariance = Eigen::Vector3d(1.0, 0.95, 0.9).asDiagonal();  // a ball: no distinctive shape
  EXPECT_EQ(dominantOrientation(nb, K, paper).source, OrientationSource::Rejected);
  // A disc in the plane x-z (normal along y): e2 ~ e1, d3D = v1 x v2 = +-y.
  nb.covariance = Eigen::Vector3d(1.0, 0.0, 0.9).asDiagonal();
  Orientation o = dominantOrientation(nb, K, paper);
  EXPECT_EQ(o.source, OrientationSource::PatchNormal);
  EXPECT_NEAR(std::abs(std::sin(o.theta)), 1.0, 0.02);  // image v direction
  // An elongated patch along x: d3D = v1 = x, signed towards the intensity mass.
  nb.covariance = Eigen::Vector3d(1.0, 0.1, 0.05).asDiagonal();
  o = dominantOrientation(nb, K, paper);
  EXPECT_EQ(o.source, OrientationSource::MajorAxis);
  EXPECT_NEAR(o.theta, 0.0, 0.05);
  nb.intensity_centroid = Eigen::Vector2d(-1.0, 0.0);
  EXPECT_NEAR(std::abs(dominantOrientation(nb, K, paper).theta), CV_PI, 0.05);
  // A disc facing the camera: its normal projects to nothing, the intensity
  // centroid decides.
  nb.point = Eigen::Vector3d(0.0, 0.0, 1.0);
  nb.covariance = Eigen::Vector3d(1.0, 0.9, 0.0).asDiagonal();
  nb.intensity_centroid = Eigen::Vector2d(0.0, 2.0);
  o = dominantOrientation(nb, K, paper);
  EXPECT_EQ(o.source, OrientationSource::IntensityCentroid);
  EXPECT_NEAR(o.theta, CV_PI / 2, 1e-9);
}

// Without shape_orientation dominantOrientation gives the intensity
// centroid; the descriptor replaces it with gradientOrientation when
// gradient_orientation is set (the default), below.
TEST(Orientation, WithoutShapeOrientationThetaIsTheIntensityCentroidAndTheGammaRuleStillRejects) {
  const DescriptorParams defaults;
  ASSERT_FALSE(defaults.shape_orientation);
  Neighbourhood nb;
  nb.point = Eigen::Vector3d(0.1, 0.05, 1.0);
  nb.intensity_centroid = Eigen::Vector2d(-1.0, 1.0);
  const Intrinsics K(500, 500, 320, 240);
  nb.covariance = Eigen::Vector3d(1.0, 0.1, 0.05).asDiagonal();  // elongated: eq. 7 would say v1
  const Orientation o = dominantOrientation(nb, K, defaults);
  EXPECT_EQ(o.source, OrientationSource::IntensityCentroid);
  EXPECT_NEAR(o.theta, 3.0 * CV_PI / 4.0, 1e-9);
  nb.covariance = Eigen::Vector3d(1.0, 0.95, 0.9).asDiagonal();
  EXPECT_EQ(dominantOrientation(nb, K, defaults).source, OrientationSource::Rejected);
}

// A plane facing the camera at 1 m with a grey ramp rising along phi, 2 grey
// levels a pixel: the gradients all point along phi, whatever phi. Beyond column 70 a white
// background 1 m farther: eq. 5 drops it, and the silhouette's gradient,
// which points at the background, has no vote.
TEST(Orientation, GradientOrientationPointsUpTheRampAndIgnoresTheSilhouette) {
  const Intrinsics K(500, 500, 60, 60);  // a disc of 20 px: the 4 cm patch at 1 m
  DescriptorParams params;
  params.gradient_orientation = true;
  for (const bool silhouette : {false, true}) {
    for (const double phi_deg : {0.0, 37.0, 130.0, 200.0, 250.0}) {
      SCOPED_TRACE(testing::Message() << "phi " << phi_deg << (silhouette ? ", silhouette" : ""));
      const double phi = phi_deg * CV_PI / 180.0;
      cv::Mat gray(120, 120, CV_8UC1), depth(120, 120, CV_32FC1, cv::Scalar(1.0f));
      for (int v = 0; v < gray.rows; ++v) {
        for (int u = 0; u < gray.cols; ++u) {
          gray.at<uchar>(v, u) = cv::saturate_cast<uchar>(128.0 + 2.0 * ((u - 60) * std::cos(phi) + (v - 60) * std::sin(phi)));
        }
      }
      if (silhouette) {
        depth.colRange(71, 120).setTo(2.0f);
        gray.colRange(71, 120).setTo(255);
      }
      const RgbdFrame frame(gray, depth, K);
      const FrameGeometry g = computeGeometry(frame, GeometryParams());
      const auto nb = selectNeighbourhood(frame, g, cv::Point2f(60, 60), 20.0f, params.background_distance);
      ASSERT_TRUE(nb.has_value());
      GreyPyramid pyramid;
      buildGreyPyramid(frame.gray(), pyramidLevelsNeeded(params), pyramid);
      const double theta = gradientOrientation(pyramid, g, *nb, 20.0f, params);
      // Within 0.4 degrees on the plane alone, measured. By the silhouette
      // the pyramid's blur still carries a little of the white past the
      // samples left out: up to 4 degrees (6.7 without the margin of
      // kBlurReach samples).
      EXPECT_NEAR(std::remainder(theta - phi, 2.0 * CV_PI), 0.0, (silhouette ? 5.0 : 1.0) * CV_PI / 180.0);
    }
  }
  // A flat patch has no gradient: theta 0.
  const RgbdFrame flat(cv::Mat(120, 120, CV_8UC1, cv::Scalar(90)), cv::Mat(120, 120, CV_32FC1, cv::Scalar(1.0f)), K);
  const FrameGeometry g = computeGeometry(flat, GeometryParams());
  const auto nb = selectNeighbourhood(flat, g, cv::Point2f(60, 60), 20.0f, params.background_distance);
  ASSERT_TRUE(nb.has_value());
  GreyPyramid pyramid;
  buildGreyPyramid(flat.gray(), pyramidLevelsNeeded(params), pyramid);
  EXPECT_EQ(gradientOrientation(pyramid, g, *nb, 20.0f, params), 0.0);
}

// The kernel (kernels/gradient_orientation.cpp) against the readable rule
// (cv::setUseOptimized(false)): keypoints of the demo scene, on texture,
// curved surfaces and silhouettes, at several radii (whole and fractional
// pyramid levels), one by the image's edge. At the default disc and at the
// widest the kernel takes, whose grid rows of 63 samples fill 63 of the 64
// bits of its words of sample kinds.
TEST(Orientation, GradientOrientationKernelEqualsTheReadableRule) {
  const DemoKeypoints demo(40);
  const FrameGeometry& g = demo.geometry;
  std::vector<cv::KeyPoint> keypoints = demo.keypoints;
  keypoints.emplace_back(cv::Point2f(3.0f, 200.0f), 7.0f);
  constexpr int kWidestDisc = (63 - 1) / 2 - 1 - kBlurReach;  // a grid row: 2 (radius + 1 + kBlurReach) + 1 samples
  for (const int patch_radius : {DescriptorParams().patch_radius, kWidestDisc}) {
    SCOPED_TRACE(testing::Message() << "patch_radius " << patch_radius);
    DescriptorParams params;
    params.gradient_orientation = true;
    params.patch_radius = patch_radius;
    const GreyPyramid grey = demo.pyramid(params);
    int compared = 0, voted = 0;
    for (size_t i = 0; i < keypoints.size(); ++i) {
      const auto nb = demo.neighbourhood(keypoints[i], params);
      if (!nb) continue;
      const float radius = 7.0f + 1.3f * static_cast<float>(i);
      const auto [fast, readable] = onBothPaths([&] { return gradientOrientation(grey, g, *nb, radius, params); });
      EXPECT_NEAR(std::remainder(fast - readable, 2.0 * CV_PI), 0.0, 1e-5) << "keypoint " << i << ", radius " << radius;
      ++compared;
      voted += readable != 0.0;
    }
    EXPECT_GE(compared, 35);
    EXPECT_GE(voted, 30);
  }
}

}  // namespace
}  // namespace risas

// Runs feature methods over dataset pairs under the protocol and scores them.
#pragma once

#include "risas/evaluation/image_noise.hpp"
#include "risas/evaluation/methods.hpp"
#include "risas/evaluation/metrics.hpp"
#include "risas/evaluation/pose_recovery.hpp"
#include "risas/evaluation/protocol.hpp"
#include "risas/intrinsics.hpp"
#include "risas/rgbd_frame.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace risas::eval {

// A pair's pose recovery over the RANSAC seeds (Evaluator's ransac_seeds):
// the share of the seeds with which the pose was recovered (5 deg / 5 cm),
// recovered closely (2 deg / 2 cm), and missed in a way the depth prefers
// (missPreferredByDepth). One seed gives 0 or 1, one draw of RANSAC's luck
// as a VO front end sees it; several give the chance of recovering the pose
// from these matches.
struct PoseShares {
  double recovered = 0.0, recovered_closely = 0.0, missed_preferred_by_depth = 0.0;
  double missed() const { return 1.0 - recovered; }
};

struct PairResult {
  Pair pair;
  std::string method;
  int reference_keypoints = 0, query_keypoints = 0;  // with a 3D point
  int dropped_reference = 0, dropped_query = 0;      // without depth: dropped
  int positives = 0;                                 // query keypoints with a correct counterpart
  Repeatability repeatability;                       // of the detector, 3 px, under the ground truth
  std::vector<Candidate> candidates;
  double auc = 0.0;
  PrPoint at_ratio;          // precision, recall, correct at the report ratio
  int distinct_correct = 0;  // its correct matches, each image point once (distinctCorrectMatches)
  PoseRecovery pose;         // RANSAC on the matches at the report ratio, the first seed
  // depthAgreement of the first seed's estimate and of the ground truth (NaN
  // without an estimate, and for synthetic_rotate, whose query depth is the
  // reference's): an estimate that explains the depth better than the
  // ground truth does, while missing it, says the two disagree there.
  double depth_agreement = NAN, depth_agreement_truth = NAN;
  PoseShares shares;         // over every seed
  double ms_per_frame = 0.0; // detect + describe, mean of the pair's two frames
};

// A pose that misses (not within 5 deg / 5 cm) although RANSAC found one
// that fits the depth better than the ground truth does (depthAgreement
// `agreement` against `truth_agreement`), by at least kDepthPreference of the
// pixels: a sign that the depth and the ground truth disagree there (with
// the 3D fit the depth pulls the pose; the images may side with either,
// PoseRefit::Reprojection shows which). False where the depth check could
// not be made (NaN).
constexpr double kDepthPreference = 0.05;
bool missPreferredByDepth(const PoseRecovery& pose, double agreement, double truth_agreement);

// The shares of `poses` (one per RANSAC seed, at least one) recovered,
// recovered closely and missed in a way the depth prefers; agreements[k] is
// poses[k]'s depthAgreement (NaN where not checked).
PoseShares poseShares(const std::vector<PoseRecovery>& poses, const std::vector<double>& agreements,
                      double truth_agreement);

// The paper's correctness distance (a match is correct when its 3D points
// agree within it under the ground truth) and the NNDR at which precision,
// recall, correct matches and the pose are reported.
constexpr double kCorrectDistance = 0.05, kReportRatio = 0.8;

class Evaluator {
 public:
  // d_min: correctness distance (metres); report_ratio: the NNDR at which
  // precision, recall and correct matches are reported; ransac_seeds: how
  // many RANSAC seeds each pair's pose recovery runs with (PoseShares; at
  // least 1, else InputError); refit: what its RANSAC motion is finally
  // fitted to (PoseRefit); noise: grey noise added to each colour image
  // before every method sees it, keyed on FramePaths::noiseKey(), so
  // an image shared by pairs is the same noisy image in each (a sigma
  // outside 0..255: InputError).
  Evaluator(std::vector<std::unique_ptr<FeatureMethod>> methods, const Intrinsics& intrinsics,
            double d_min = kCorrectDistance, double report_ratio = kReportRatio, int ransac_seeds = 1,
            PoseRefit refit = PoseRefit::Umeyama, const ImageNoise& noise = ImageNoise());

  // Every method on the pair; a reference frame shared by several pairs is
  // processed once per method. InputError for unreadable frames.
  std::vector<PairResult> evaluate(const Pair& pair);

  const std::vector<std::unique_ptr<FeatureMethod>>& methods() const { return methods_; }

 private:
  struct Processed {
    MethodOutput output;
    double ms = 0.0;
  };
  struct LoadedFrame {
    cv::Mat bgr;
    RgbdFrame frame;
  };
  LoadedFrame load(const FramePaths& paths) const;
  Processed process(const FeatureMethod& method, const LoadedFrame& frame);

  std::vector<std::unique_ptr<FeatureMethod>> methods_;
  Intrinsics intrinsics_;
  double d_min_, report_ratio_;
  int ransac_seeds_;
  PoseRefit refit_;
  ImageNoise noise_;
  std::map<std::pair<std::string, std::string>, Processed> reference_cache_;  // (method, rgb path)
};

// Reports, written into `dir`:
//   pairs.csv     one row per pair and method: the pose columns are the
//                 first seed's, the success columns the shares over all
//   curves.csv    per scene, sequence and method: the PR curve of all its pairs pooled
//   summary.csv   per scene, sequence and method: mean PR-AUC, precision,
//                 recall, correct matches and distinct correct matches at
//                 the report ratio, pose
//                 success rates at 5 deg / 5 cm and 2 deg / 2 cm (the
//                 pairs' PoseShares averaged), mean inliers, detector
//                 repeatability (3 px), ms/frame, misses and the misses
//                 the depth prefers (sums of the pairs' shares)
//   summary.md    per scene type two markdown tables: mean PR-AUC (the best
//                 of each sequence in bold), and pose recovery (its title
//                 names the reprojection refit where `refit` is that)
//   scale.csv     correct-match percentage (correct / matches) per scale step
void writeReports(const std::string& dir, const std::vector<PairResult>& results, double report_ratio,
                  PoseRefit refit = PoseRefit::Umeyama);

}  // namespace risas::eval

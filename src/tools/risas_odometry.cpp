// risas_odometry: risas::Odometry over a TUM RGB-D folder, written as a TUM
// trajectory (one line per frame given, lost frames at their held pose),
// scored against the folder's ground truth (ATE, RPE) when it has one.
#include "cli.hpp"
#include "image_noise_options.hpp"

#include "risas/errors.hpp"
#include "risas/evaluation/image_noise.hpp"
#include "risas/evaluation/median.hpp"
#include "risas/evaluation/methods.hpp"
#include "risas/evaluation/protocol.hpp"
#include "risas/evaluation/trajectory.hpp"
#include "risas/io.hpp"
#include "risas/odometry.hpp"
#include "risas/risas.hpp"
#include "risas/tum_sequence.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

// The association's tolerance (associate.py's, kTumMaxDifference) as the
// messages print it, in seconds.
const std::string kToleranceText = [] {
  std::ostringstream text;
  text << risas::kTumMaxDifference;
  return text.str();
}();

// ORB (1000 features, OpenCV's defaults) with each keypoint's 3D point from
// the median depth of its 3x3 neighbourhood, as the evaluation takes it;
// keypoints without depth are left out. one_per_point: the strongest of the
// keypoints within 3 px only, as the evaluation's ORB-distinct (ORB finds
// most corners again at other pyramid levels; docs/odometry.md).
risas::Features orbFeatures(const cv::Ptr<cv::ORB>& orb, const risas::RgbdFrame& frame, bool one_per_point) {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  risas::eval::detectAndDescribe(
      *orb, frame.gray(), one_per_point ? risas::eval::Keypoints::OnePerImagePoint : risas::eval::Keypoints::All,
      keypoints, descriptors);
  risas::Features f;
  f.descriptors = cv::Mat(0, descriptors.cols, descriptors.type());
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const cv::Point3f p = risas::eval::keypointPoint(frame.depth(), frame.intrinsics(), keypoints[i].pt);
    if (std::isnan(p.z)) continue;
    f.keypoints.push_back(keypoints[i]);
    f.descriptors.push_back(descriptors.row(static_cast<int>(i)));
    f.geometry.push_back({p, cv::Vec3f(0, 0, 0), 0.0f});
  }
  return f;
}

// One consistency line: `what` (c.poses `counted`): the position's and the
// rotation's mean |e|^2 / mean sigma^2, and the share within two sigma.
void printConsistency(const std::string& what, const std::string& counted,
                      const risas::eval::CovarianceConsistency& c) {
  std::cout << std::fixed << std::setprecision(2) << what << " (" << c.poses << " " << counted
            << "): position mean |e|^2 / mean sigma^2 " << c.position_ratio << ", |e| < 2 sigma on "
            << std::setprecision(0) << 100.0 * c.within_two_sigma << " %; rotation " << std::setprecision(2)
            << c.rotation_ratio << "\n";
}

// The first seed's reported covariance against its drift, over the tracked
// frames that have ground truth (a lost frame's held pose is not measured);
// printed and returned, none when fewer than 2 poses have it.
std::optional<risas::eval::CovarianceConsistency> printCovarianceConsistency(
    const risas::eval::AssociatedTrajectory& tracked, const std::vector<Eigen::Matrix<double, 6, 6>>& covariances) {
  if (tracked.estimate.size() < 2) return std::nullopt;
  std::vector<Eigen::Matrix<double, 6, 6>> associated;
  for (size_t i : tracked.estimate_index) associated.push_back(covariances[i]);
  const risas::eval::CovarianceConsistency c = risas::eval::covarianceConsistency(tracked, associated);
  printConsistency("Covariance against the drift from the first tracked pose",
                   "poses, no alignment; 1 is consistent, above 1 overconfident", c);
  return c;
}

// The first seed's frame-to-frame motions (what the ROS node's twist is
// made of) against the truth's between the same frames; printed and
// returned, none when no motion has the truth's.
std::optional<risas::eval::CovarianceConsistency> printMotionConsistency(
    const risas::eval::AssociatedTrajectory& all_frames, const std::vector<risas::eval::FrameMotion>& motions) {
  const risas::eval::CovarianceConsistency c = risas::eval::motionConsistency(all_frames, motions);
  if (c.poses == 0) return std::nullopt;
  printConsistency("Frame-to-frame motion's covariance (the twist's) against the truth's motion", "motions", c);
  return c;
}

double mean(const std::vector<double>& values) {
  return std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

// The features of a recording's frames for a set of chains, extracted once
// a frame: the seeds and the chains change only the tracking. A frame's
// are kept (about 0.3 MB a frame at 1000 keypoints) until every chain that
// has the frame has released it.
class FeatureCache {
 public:
  // features_name: RISAS (with params), ORB or ORB-distinct. noise: grey
  // noise added to each colour image before its features (sigma 0: none),
  // frame i's withImageNoise(sigma, seed, i), the same in every chain.
  FeatureCache(const risas::TumSequence& sequence, const risas::Intrinsics& K, const std::string& features_name,
               const risas::RisasParams& params, const risas::eval::ImageNoise& noise,
               const std::vector<std::vector<size_t>>& chains)
      : sequence_(sequence),
        K_(K),
        features_name_(features_name),
        noise_(noise),
        risas_(risas::Risas::create(params)),
        orb_(cv::ORB::create(1000)),
        uses_(sequence.frames.size(), 0),
        kept_(sequence.frames.size()) {
    for (const std::vector<size_t>& chain : chains) {
      for (size_t i : chain) ++uses_[i];
    }
  }

  // Frame i's features, extracted on the first call.
  const risas::Features& get(size_t i) {
    if (!kept_[i]) {
      risas::RgbdImages images = risas::readRgbdImages(sequence_.frames[i].rgb, sequence_.frames[i].depth);
      if (noise_.sigma > 0.0) images.bgr = risas::eval::withImageNoise(images.bgr, noise_.sigma, noise_.seed, i);
      const risas::RgbdFrame frame = risas::rgbdFrameOf(images, K_, risas::kTumDepthUnitsPerMetre);
      kept_[i] = features_name_ == "RISAS" ? risas_->extract(frame)
                                           : orbFeatures(orb_, frame, features_name_ == "ORB-distinct");
    }
    return *kept_[i];
  }

  // RISAS, ORB or ORB-distinct, as the summary names the features.
  const std::string& name() const { return features_name_; }

  // One chain is done with frame i; the last one's release drops them.
  void release(size_t i) {
    if (--uses_[i] == 0) kept_[i].reset();
  }

 private:
  const risas::TumSequence& sequence_;
  const risas::Intrinsics K_;
  const std::string features_name_;
  const risas::eval::ImageNoise noise_;
  const cv::Ptr<risas::Risas> risas_;
  const cv::Ptr<cv::ORB> orb_;
  std::vector<int> uses_;  // per frame: the chains that have not released it
  std::vector<std::optional<risas::Features>> kept_;
};

// What every chain of one run shares: the recording, its features and the
// options that say how to track and score.
struct Run {
  std::string tum;
  const risas::TumSequence* sequence = nullptr;
  const risas::RisasParams* params = nullptr;
  FeatureCache* features = nullptr;
  bool scored = false;  // groundtruth.txt is there: its poses are the sequence's ground_truth
  int seeds = 1, delta = 1;
};

// What one chain reports: each seed's ATE RMSE (none when the chain cannot
// be scored), and its first seed's covariance checks where they could be
// made.
struct ChainResult {
  std::vector<double> ates;
  std::optional<risas::eval::CovarianceConsistency> drift, motion;
};

// The chain of frames `chain` (indices into the sequence) tracked once per
// RANSAC seed, seeded motion.seed + k. Unless `out` (`frames_csv_path`) is
// empty, the first seed's trajectory (per-frame table) is written there. Prints the
// first seed's summary, ATE, RPE and covariance checks, and the spread over
// the seeds, and returns them.
ChainResult trackChain(const Run& run, const std::vector<size_t>& chain, const std::string& out,
                       const std::string& frames_csv_path) {
  ChainResult result;
  std::vector<double>& ates = result.ates;
  const std::vector<risas::StampedPose>& truth = run.sequence->ground_truth;
  const int runs = run.scored ? run.seeds : 1;  // without a ground truth the other seeds would score nothing
  for (int k = 0; k < runs; ++k) {
    risas::MotionParams motion = run.params->motion;
    motion.seed = run.params->motion.seed + static_cast<unsigned int>(k);
    risas::Odometry odometry(run.params->odometry, run.params->match, motion);
    std::vector<risas::StampedPose> trajectory, tracked;
    std::vector<Eigen::Matrix<double, 6, 6>> tracked_covariances;
    std::vector<risas::eval::FrameMotion> motions;
    // The first seed's per-frame table, written whole after its run.
    const bool write_frames = k == 0 && !frames_csv_path.empty();
    std::ostringstream frames_csv;
    if (write_frames) {
      frames_csv << "stamp,tracked,keyframe,features,matches,inliers,rmse,position_sd,rotation_sd_deg\n"
                 << std::fixed << std::setprecision(6);
    }
    for (size_t j = 0; j < chain.size(); ++j) {
      const risas::Features& features = run.features->get(chain[j]);
      const double stamp = run.sequence->frames[chain[j]].stamp;
      const risas::OdometryResult r = odometry.track(features);
      trajectory.push_back({stamp, r.world_T_camera});
      if (r.tracked) {
        tracked.push_back({stamp, r.world_T_camera});
        tracked_covariances.push_back(r.covariance);
      }
      if (r.motion_tracked) motions.push_back({j - 1, j, r.previous_T_camera, r.motion_covariance});
      if (write_frames) {
        frames_csv << stamp << "," << r.tracked << "," << r.new_keyframe << "," << features.keypoints.size() << ","
                   << r.matches << "," << r.inliers << "," << r.rmse << ","
                   << std::sqrt(r.covariance.topLeftCorner<3, 3>().trace()) << ","
                   << std::sqrt(r.covariance.bottomRightCorner<3, 3>().trace()) * 180.0 / M_PI << "\n";
      }
      if (k == runs - 1) run.features->release(chain[j]);
    }
    const risas::eval::AssociatedTrajectory all_frames =
        run.scored ? risas::eval::associate(trajectory, truth) : risas::eval::AssociatedTrajectory();
    // The trajectory is the result; the score, which groundtruth.txt's
    // presence asks for, needs three frames with ground truth.
    const size_t with_truth = all_frames.estimate.size();
    const bool scorable = run.scored && with_truth >= 3;
    const risas::eval::TrajectoryError e =
        scorable ? risas::eval::trajectoryError(all_frames, run.delta) : risas::eval::TrajectoryError();
    if (scorable) ates.push_back(e.ate_rmse);
    if (k > 0) continue;
    if (write_frames) risas::writeTextFile(frames_csv_path, frames_csv.str(), "frame table");
    if (!out.empty()) risas::writeTumTrajectory(out, trajectory);
    std::cout << run.features->name() << " odometry: " << odometry.frames() << " frames, " << odometry.lostFrames()
              << " not tracked, " << odometry.recoveries() << " recoveries, " << odometry.keyframes() << " keyframes"
              << (out.empty() ? "" : "; trajectory written to " + out) << "\n";
    if (!run.scored) {
      std::cout << "Not scored: " << run.tum << " has no groundtruth.txt"
                << (run.seeds > 1 ? "; one RANSAC seed run, not " + std::to_string(run.seeds) : "") << "\n";
      continue;
    }
    if (!scorable) {
      std::cout << "Not scored: the ATE needs 3 frames with ground truth (within " << kToleranceText << " s), "
                << with_truth << " have it\n";
      continue;
    }
    std::cout << std::fixed << std::setprecision(4) << "ATE RMSE " << e.ate_rmse << " m (mean " << e.ate_mean
              << ", median " << e.ate_median << ", max " << e.ate_max << ") over " << e.poses << " poses\n";
    if (e.rpe_pairs == 0) {
      std::cout << "RPE (" << run.delta << " frame): no two frames with ground truth that far apart\n";
    } else {
      std::cout << "RPE (" << run.delta << " frame) translation RMSE " << e.rpe_translation_rmse
                << " m, rotation RMSE " << std::setprecision(3) << e.rpe_rotation_rmse_deg << " deg over "
                << e.rpe_pairs << " pairs\n";
    }
    result.drift = printCovarianceConsistency(risas::eval::associate(tracked, truth), tracked_covariances);
    result.motion = printMotionConsistency(all_frames, motions);
  }
  if (!ates.empty() && run.seeds > 1) {
    // One seed is one draw: where inliers are few, which keyframe poses
    // RANSAC finds is luck, and the chain carries it (docs/odometry.md).
    // The median beside the mean: one unlucky seed moves the mean alone.
    const auto [lowest, highest] = std::minmax_element(ates.begin(), ates.end());
    std::cout << std::fixed << std::setprecision(4) << "ATE RMSE over " << run.seeds << " RANSAC seeds: mean "
              << mean(ates) << " m, median " << risas::eval::median(ates) << " m, from " << *lowest << " to "
              << *highest << " m\n";
  }
  return result;
}

// "mean 0.0295 m, from 0.0267 to 0.0346 m": values' mean and range, each
// number with `precision` decimals and followed by `unit`.
std::string meanAndRange(const std::vector<double>& values, int precision, const std::string& unit) {
  const auto [lowest, highest] = std::minmax_element(values.begin(), values.end());
  std::ostringstream text;
  text << std::fixed << std::setprecision(precision) << "mean " << mean(values) << unit << ", from " << *lowest
       << " to " << *highest << unit;
  return text.str();
}

// "over 5 chains" or, where some chain had no figure, "over 4 of 5 chains".
std::string overChains(size_t with_figure, size_t chains) {
  return "over " + (with_figure < chains ? std::to_string(with_figure) + " of " : "") + std::to_string(chains) +
         " chains";
}

// One covariance check over the chains (`what`): the mean and range of the
// chains' position and rotation ratios, each chain's first seed's, so that
// a user sees whether one chain's figure holds where the keyframes fall
// elsewhere (docs/odometry.md).
void printChainsConsistency(const std::string& what, const std::vector<risas::eval::CovarianceConsistency>& checks,
                            size_t chains) {
  if (checks.empty()) return;
  std::vector<double> position, rotation;
  for (const risas::eval::CovarianceConsistency& c : checks) {
    position.push_back(c.position_ratio);
    rotation.push_back(c.rotation_ratio);
  }
  std::cout << what << " " << overChains(checks.size(), chains)
            << ", each chain's first seed: position mean |e|^2 / mean sigma^2 " << meanAndRange(position, 2, "")
            << "; rotation " << meanAndRange(rotation, 2, "") << "\n";
}

// "0, 7, 14" for a list of starting frames.
std::string joined(const std::vector<int>& numbers) {
  std::string text;
  for (int n : numbers) text += (text.empty() ? "" : ", ") + std::to_string(n);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_odometry", [&] {
    std::vector<risas::cli::Option> options = {
        {"tum", "DIR", "TUM RGB-D folder: rgb.txt, depth.txt (5000 units per metre), groundtruth.txt"},
        {"out", "T.txt", "trajectory to write (TUM format: timestamp tx ty tz qx qy qz qw); the first chain's"},
        {"features", "NAME",
         "RISAS (default), ORB (1000, with depth) or ORB-distinct (ORB's strongest keypoint within 3 px only): the "
         "same odometry on each"},
        {"frames", "CSV",
         "also write per frame: stamp, tracked, keyframe, features, matches, inliers, rmse and the pose's standard "
         "deviations (position m, rotation deg: the roots of the covariance's traces); the first chain's"},
        {"step", "N", "track every N-th frame: the camera at 1/N of its rate (default 1)"},
        {"start", "S[,S...]",
         "track from frame S (0 = the first; default 0); several starts track a chain of frames from each"},
        {"delta", "N", "RPE over frame pairs N apart in the chain, N x step of the camera's (default 1)"},
        {"truth-offset", "S",
         "seconds added to groundtruth.txt's stamps before each frame takes the nearest (within " + kToleranceText +
             " s): for a motion capture whose clock is off the camera's (default 0; TUM's evaluate_ate.py --offset "
             "shifts the other file)"},
        {"max-frames", "N", "track at most N frames a chain"},
        {"ransac-seeds", "N", "also run with RANSAC seeds motion.seed + 1 .. N - 1 and print the spread (default 1)"}};
    for (const risas::cli::Option& o : risas::cli::imageNoiseOptions("each frame's is the same in every chain")) {
      options.push_back(o);
    }
    options.push_back(risas::cli::paramsOption());
    for (const risas::cli::Option& o : risas::cli::intrinsicsOptions()) options.push_back(o);
    const risas::cli::Args args(
        argc, argv,
        "risas_odometry --tum DIR --out T.txt --intrinsics K.txt | --fx F --fy F --cx C --cy C\n"
        "               [--features RISAS|ORB|ORB-distinct] [--params P.yml] [--frames F.csv] [--delta 1]\n"
        "               [--step N] [--start S[,S...]] [--ransac-seeds N] [--truth-offset S]\n"
        "               [--image-noise SIGMA [--noise-seed N]]\n"
        "Frame-to-keyframe RGB-D odometry (risas::Odometry) over a TUM-layout sequence; writes the\n"
        "trajectory and, with groundtruth.txt, prints ATE RMSE (after a rigid alignment), RPE and how the\n"
        "reported covariance compares with the drift (mean |e|^2 / mean sigma^2, 1 when consistent), and the\n"
        "frame-to-frame motion's (a twist's) with the truth's motion.\n"
        "With --ransac-seeds N the same features are tracked N times, RANSAC seeded motion.seed + k:\n"
        "the trajectory written is the first seed's, and the ATE's mean, median and range over the N follow.\n"
        "--image-noise SIGMA tracks the recording as a noisier camera would see it; over several --noise-seed\n"
        "values the ATE's spread is what noise alone moves, to weigh a difference between settings against.\n"
        "--step N tracks frames S, S + N, S + 2N, ... (S from --start): the camera at a lower rate. Where the\n"
        "keyframes fall moves the ATE (docs/odometry.md): with several starts (--start 0,7,14 or, with\n"
        "--step 3, --start 0,1,2) each start is a chain of its own, reported in turn, and the mean and range\n"
        "over the chains of each chain's mean ATE and of its covariance checks follow; --out and --frames hold\n"
        "the first chain's.\n"
        "Plot it with scripts/plot_trajectory.py GT.txt T.txt [...] --out P.png.",
        options);
    cv::setNumThreads(1);
    const std::string out = args.get("out"), features_name = args.get("features", "RISAS");
    if (features_name != "RISAS" && features_name != "ORB" && features_name != "ORB-distinct") {
      throw risas::cli::UsageError("--features is RISAS, ORB or ORB-distinct, not '" + features_name + "'");
    }
    risas::cli::requireWritable(out);
    if (args.has("frames")) risas::cli::requireWritable(args.get("frames"));
    const risas::RisasParams params = risas::cli::paramsFrom(args);
    const risas::Intrinsics K = risas::cli::intrinsicsFrom(args);
    const int max_frames = args.getInt("max-frames", 100000000, 1, 100000000);
    const int step = args.getInt("step", 1, 1, 1000000);
    const std::vector<int> starts = args.getIntList("start", "0", 0, 100000000);
    const double truth_offset = args.getDouble("truth-offset", 0.0);
    const risas::eval::ImageNoise noise = risas::cli::imageNoiseFrom(args);
    const risas::TumSequence sequence =
        risas::cli::readTumSequenceNoting("risas_odometry", args.get("tum"), truth_offset);
    Run run;
    run.tum = args.get("tum");
    run.sequence = &sequence;
    run.params = &params;
    run.seeds = args.getInt("ransac-seeds", 1, 1, 1000);
    run.delta = args.getInt("delta", 1, 1, 1000000);
    const std::filesystem::path gt = std::filesystem::path(run.tum) / "groundtruth.txt";
    run.scored = std::filesystem::exists(gt);
    if (!run.scored) args.refuse({"truth-offset"}, "without " + gt.string());

    // The chains: frames start, start + step, ... from each start.
    std::vector<std::vector<size_t>> chains;
    for (int start : starts) {
      if (static_cast<size_t>(start) >= sequence.frames.size()) {
        throw risas::InputError("--start " + std::to_string(start) + " is past " + run.tum + "'s " +
                                std::to_string(sequence.frames.size()) + " frames (the first is 0)");
      }
      std::vector<size_t> chain;
      for (size_t i = static_cast<size_t>(start);
           i < sequence.frames.size() && chain.size() < static_cast<size_t>(max_frames); i += static_cast<size_t>(step)) {
        chain.push_back(i);
      }
      chains.push_back(chain);
    }

    FeatureCache features(sequence, K, features_name, params, noise, chains);
    risas::cli::noteImageNoise(noise);
    run.features = &features;

    std::vector<double> chain_ates;  // each scored chain's mean over the seeds
    std::vector<risas::eval::CovarianceConsistency> drifts, motions;  // each chain's first seed's, where made
    for (size_t c = 0; c < chains.size(); ++c) {
      if (chains.size() > 1) std::cout << "Chain from frame " << starts[c] << ", step " << step << ":\n";
      const bool first = c == 0;
      const ChainResult result = trackChain(run, chains[c], first ? out : "", first ? args.get("frames", "") : "");
      if (!result.ates.empty()) chain_ates.push_back(mean(result.ates));
      if (result.drift) drifts.push_back(*result.drift);
      if (result.motion) motions.push_back(*result.motion);
    }
    if (chains.size() > 1 && !chain_ates.empty()) {
      std::cout << "ATE RMSE " << overChains(chain_ates.size(), chains.size()) << " (step " << step
                << ", from frames " << joined(starts) << "), each chain's mean over " << run.seeds << " RANSAC seed"
                << (run.seeds > 1 ? "s" : "") << ": " << meanAndRange(chain_ates, 4, " m") << "\n";
    }
    if (chains.size() > 1) {
      printChainsConsistency("Covariance against the drift", drifts, chains.size());
      printChainsConsistency("Frame-to-frame motion's covariance (the twist's)", motions, chains.size());
    }
    return 0;
  });
}

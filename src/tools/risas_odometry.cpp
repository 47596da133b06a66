// risas_odometry: risas::Odometry over a TUM RGB-D folder, written as a TUM
// trajectory (one line per frame given, lost frames at their held pose),
// scored against the folder's ground truth (ATE, RPE) when it has one.
#include "cli.hpp"

#include "risas/errors.hpp"
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
#include <sstream>
#include <string>
#include <vector>

namespace {

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
// frames that have ground truth (a lost frame's held pose is not measured).
void printCovarianceConsistency(const risas::eval::AssociatedTrajectory& tracked,
                                const std::vector<Eigen::Matrix<double, 6, 6>>& covariances) {
  if (tracked.estimate.size() < 2) return;
  std::vector<Eigen::Matrix<double, 6, 6>> associated;
  for (size_t i : tracked.estimate_index) associated.push_back(covariances[i]);
  printConsistency("Covariance against the drift from the first tracked pose",
                   "poses, no alignment; 1 is consistent, above 1 overconfident",
                   risas::eval::covarianceConsistency(tracked, associated));
}

// The first seed's frame-to-frame motions (what the ROS node's twist is
// made of) against the truth's between the same frames.
void printMotionConsistency(const risas::eval::AssociatedTrajectory& all_frames,
                            const std::vector<risas::eval::FrameMotion>& motions) {
  const risas::eval::CovarianceConsistency c = risas::eval::motionConsistency(all_frames, motions);
  if (c.poses == 0) return;
  printConsistency("Frame-to-frame motion's covariance (the twist's) against the truth's motion", "motions", c);
}

}  // namespace

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_odometry", [&] {
    std::vector<risas::cli::Option> options = {
        {"tum", "DIR", "TUM RGB-D folder: rgb.txt, depth.txt (5000 units per metre), groundtruth.txt"},
        {"out", "T.txt", "trajectory to write (TUM format: timestamp tx ty tz qx qy qz qw)"},
        {"features", "NAME",
         "RISAS (default), ORB (1000, with depth) or ORB-distinct (ORB's strongest keypoint within 3 px only): the "
         "same odometry on each"},
        {"frames", "CSV",
         "also write per frame: stamp, tracked, keyframe, features, matches, inliers, rmse and the pose's standard "
         "deviations (position m, rotation deg: the roots of the covariance's traces)"},
        {"delta", "N", "RPE over frame pairs N apart (default 1)"},
        {"max-frames", "N", "stop after N frames"},
        {"ransac-seeds", "N", "also run with RANSAC seeds motion.seed + 1 .. N - 1 and print the spread (default 1)"},
        risas::cli::paramsOption()};
    for (const risas::cli::Option& o : risas::cli::intrinsicsOptions()) options.push_back(o);
    const risas::cli::Args args(
        argc, argv,
        "risas_odometry --tum DIR --out T.txt --intrinsics K.txt | --fx F --fy F --cx C --cy C\n"
        "               [--features RISAS|ORB|ORB-distinct] [--params P.yml] [--frames F.csv] [--delta 1] [--ransac-seeds N]\n"
        "Frame-to-keyframe RGB-D odometry (risas::Odometry) over a TUM-layout sequence; writes the\n"
        "trajectory and, with groundtruth.txt, prints ATE RMSE (after a rigid alignment), RPE and how the\n"
        "reported covariance compares with the drift (mean |e|^2 / mean sigma^2, 1 when consistent), and the\n"
        "frame-to-frame motion's (a twist's) with the truth's motion.\n"
        "With --ransac-seeds N the same features are tracked N times, RANSAC seeded motion.seed + k:\n"
        "the trajectory written is the first seed's, and the ATE's mean, median and range over the N follow.\n"
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
    const risas::TumSequence sequence = risas::cli::readTumSequenceNoting("risas_odometry", args.get("tum"));
    const int max_frames = args.getInt("max-frames", static_cast<int>(sequence.frames.size()), 1, 100000000);
    const int seeds = args.getInt("ransac-seeds", 1, 1, 1000);
    const int delta = args.getInt("delta", 1, 1, 1000000);
    const std::filesystem::path gt = std::filesystem::path(args.get("tum")) / "groundtruth.txt";
    const bool scored = std::filesystem::exists(gt);

    // Features once per frame: the seeds change only the tracking. The
    // first seed tracks them as they come; more seeds keep them (about
    // 0.3 MB a frame at 1000 keypoints) for the runs after it.
    const auto risas = risas::Risas::create(params);
    const cv::Ptr<cv::ORB> orb = cv::ORB::create(1000);
    const size_t count = static_cast<size_t>(std::min<int>(max_frames, static_cast<int>(sequence.frames.size())));
    std::vector<risas::Features> kept;
    const auto extract = [&](size_t i) {
      const risas::RgbdFrame frame = risas::loadTumFrame(sequence.frames[i], K);
      return features_name == "RISAS" ? risas->extract(frame) : orbFeatures(orb, frame, features_name == "ORB-distinct");
    };
    const std::vector<risas::StampedPose> truth =
        scored ? risas::readTumTrajectory(gt.string()) : std::vector<risas::StampedPose>();
    std::vector<double> ates;
    const int runs = scored ? seeds : 1;  // without a ground truth the other seeds would score nothing
    for (int k = 0; k < runs; ++k) {
      risas::MotionParams motion = params.motion;
      motion.seed = params.motion.seed + static_cast<unsigned int>(k);
      risas::Odometry odometry(params.odometry, params.match, motion);
      std::vector<risas::StampedPose> trajectory, tracked;
      std::vector<Eigen::Matrix<double, 6, 6>> tracked_covariances;
      std::vector<risas::eval::FrameMotion> motions;
      // The first seed's per-frame table, written whole after its run.
      const bool write_frames = k == 0 && args.has("frames");
      std::ostringstream frames_csv;
      if (write_frames) {
        frames_csv << "stamp,tracked,keyframe,features,matches,inliers,rmse,position_sd,rotation_sd_deg\n"
                   << std::fixed << std::setprecision(6);
      }
      for (size_t i = 0; i < count; ++i) {
        risas::Features extracted;
        if (k == 0) {
          extracted = extract(i);
          if (runs > 1) kept.push_back(extracted);
        }
        const risas::Features& features = k == 0 ? extracted : kept[i];
        const double stamp = sequence.frames[i].stamp;
        const risas::OdometryResult r = odometry.track(features);
        trajectory.push_back({stamp, r.world_T_camera});
        if (r.tracked) {
          tracked.push_back({stamp, r.world_T_camera});
          tracked_covariances.push_back(r.covariance);
        }
        if (r.motion_tracked) motions.push_back({i - 1, i, r.previous_T_camera, r.motion_covariance});
        if (write_frames) {
          frames_csv << stamp << "," << r.tracked << "," << r.new_keyframe << "," << features.keypoints.size()
                     << "," << r.matches << "," << r.inliers << "," << r.rmse << ","
                     << std::sqrt(r.covariance.topLeftCorner<3, 3>().trace()) << ","
                     << std::sqrt(r.covariance.bottomRightCorner<3, 3>().trace()) * 180.0 / M_PI << "\n";
        }
      }
      const risas::eval::AssociatedTrajectory all_frames =
          scored ? risas::eval::associate(trajectory, truth) : risas::eval::AssociatedTrajectory();
      // The trajectory is the result; the score, which groundtruth.txt's
      // presence asks for, needs three frames with ground truth.
      const size_t with_truth = all_frames.estimate.size();
      const bool scorable = scored && with_truth >= 3;
      const risas::eval::TrajectoryError e =
          scorable ? risas::eval::trajectoryError(all_frames, delta) : risas::eval::TrajectoryError();
      if (scorable) ates.push_back(e.ate_rmse);
      if (k > 0) continue;
      if (write_frames) risas::writeTextFile(args.get("frames"), frames_csv.str(), "frame table");
      risas::writeTumTrajectory(out, trajectory);
      std::cout << features_name << " odometry: " << odometry.frames() << " frames, " << odometry.lostFrames()
                << " not tracked, " << odometry.recoveries() << " recoveries, " << odometry.keyframes()
                << " keyframes; trajectory written to " << out << "\n";
      if (!scored) {
        std::cout << "Not scored: " << args.get("tum") << " has no groundtruth.txt"
                  << (seeds > 1 ? "; one RANSAC seed run, not " + std::to_string(seeds) : "") << "\n";
        continue;
      }
      if (!scorable) {
        std::cout << "Not scored: the ATE needs 3 frames with ground truth (within 0.02 s), " << with_truth
                  << " have it\n";
        continue;
      }
      std::cout << std::fixed << std::setprecision(4) << "ATE RMSE " << e.ate_rmse << " m (mean " << e.ate_mean
                << ", median " << e.ate_median << ", max " << e.ate_max << ") over " << e.poses << " poses\n";
      if (e.rpe_pairs == 0) {
        std::cout << "RPE (" << delta << " frame): no two frames with ground truth that far apart\n";
      } else {
        std::cout << "RPE (" << delta << " frame) translation RMSE " << e.rpe_translation_rmse << " m, rotation RMSE "
                  << std::setprecision(3) << e.rpe_rotation_rmse_deg << " deg over " << e.rpe_pairs << " pairs\n";
      }
      printCovarianceConsistency(risas::eval::associate(tracked, truth), tracked_covariances);
      printMotionConsistency(all_frames, motions);
    }
    if (!ates.empty() && seeds > 1) {
      // One seed is one draw: where inliers are few, which keyframe poses
      // RANSAC finds is luck, and the chain carries it (docs/odometry.md).
      // The median beside the mean: one unlucky seed moves the mean alone.
      const auto [lowest, highest] = std::minmax_element(ates.begin(), ates.end());
      std::cout << std::fixed << std::setprecision(4) << "ATE RMSE over " << seeds << " RANSAC seeds: mean "
                << std::accumulate(ates.begin(), ates.end(), 0.0) / seeds << " m, median " << risas::eval::median(ates)
                << " m, from " << *lowest << " to " << *highest << " m\n";
    }
    return 0;
  });
}

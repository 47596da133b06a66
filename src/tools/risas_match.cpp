// risas_match: match two RGB-D frames, estimate their rigid motion, draw the overlay.
#include "cli.hpp"

#include "risas/io.hpp"
#include "risas/matcher.hpp"
#include "risas/motion.hpp"
#include "risas/overlay.hpp"
#include "risas/risas.hpp"

#include <Eigen/Geometry>

#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>

namespace {

std::string describeMotion(const Eigen::Isometry3d& T) {
  const Eigen::AngleAxisd aa(T.linear());
  char text[200];
  std::snprintf(text, sizeof text, "rotation %.2f deg, translation [%.3f %.3f %.3f] m (|t| %.3f m)",
                aa.angle() * 180.0 / CV_PI, T.translation().x(), T.translation().y(), T.translation().z(),
                T.translation().norm());
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_match", [&] {
    using risas::cli::Option;
    std::vector<Option> options = {
        {"rgb1", "R1.png", "first (reference) colour image"},
        {"depth1", "D1.png", "first depth image (16-bit; millimetres unless --depth-units)"},
        {"rgb2", "R2.png", "second colour image"},
        {"depth2", "D2.png", "second depth image (16-bit, as the first)"},
        {"overlay", "O.png", "write the side-by-side overlay here (first frame left)"},
        {"ratio", "r", "NNDR ratio (default: the parameter file's, 0.8)"},
        {"cross-check", "", "keep only mutual nearest neighbours"},
        {"gt-rotation", "R.txt", "ground-truth rotation (3x3) with p1 = R p2 + t, to score the matches"},
        {"gt-translation", "T.txt", "ground-truth translation (3x1, metres)"}};
    for (const Option& o : risas::cli::intrinsicsOptions()) options.push_back(o);
    options.push_back(risas::cli::depthUnitsOption());
    options.push_back(risas::cli::paramsOption());
    const risas::cli::Args args(
        argc, argv,
        "risas_match --rgb1 R1.png --depth1 D1.png --rgb2 R2.png --depth2 D2.png --intrinsics K.txt\n"
        "            [--overlay O.png] [--ratio 0.8] [--cross-check] [--params P.yml]\n"
        "Matches the RISAS features of frame 2 to frame 1 (NNDR), estimates the rigid motion\n"
        "p1 = R p2 + t by RANSAC and draws the matches: inliers green, outliers red.",
        options);
    risas::RisasParams params = risas::cli::paramsFrom(args);
    params.match.ratio = args.getDouble("ratio", params.match.ratio);
    params.match.cross_check = params.match.cross_check || args.has("cross-check");
    params.validate();
    if (args.has("overlay")) {
      risas::cli::requireWritable(args.get("overlay"));
      risas::requireImageWriter(args.get("overlay"), "overlay");
    }
    const risas::Intrinsics K = risas::cli::intrinsicsFrom(args);
    const double depth_units = risas::cli::depthUnitsFrom(args);
    // The ground truth read before the work, so that a bad file stops it.
    std::optional<Eigen::Isometry3d> gt;
    if (args.has("gt-rotation") || args.has("gt-translation")) {
      gt = risas::readPoseFiles(args.get("gt-rotation"), args.get("gt-translation"));
    }
    const risas::RgbdFrame frame1 = risas::loadRgbdFrame(args.get("rgb1"), args.get("depth1"), K, depth_units);
    const risas::RgbdFrame frame2 = risas::loadRgbdFrame(args.get("rgb2"), args.get("depth2"), K, depth_units);

    const auto risas = risas::Risas::create(params);
    const risas::Features f1 = risas->extract(frame1), f2 = risas->extract(frame2);
    const auto matches = risas::matchDescriptors(f2.descriptors, f1.descriptors, params.match);
    const risas::MotionEstimate motion = risas::estimateRigidMotion(f2.points(), f1.points(), matches, params.motion);

    std::cout << "frame 1: " << f1.keypoints.size() << " features, frame 2: " << f2.keypoints.size() << " features\n";
    std::cout << "matches: " << matches.size() << " (NNDR " << params.match.ratio << "), RANSAC inliers: "
              << motion.num_inliers << "\n";
    if (motion.valid) {
      std::cout << "motion (p1 = R p2 + t): " << describeMotion(motion.train_T_query) << ", inlier rmse "
                << motion.rmse * 1000.0 << " mm\n";
      const Eigen::Matrix4d M = motion.train_T_query.matrix();
      std::cout << M << "\n";
    } else {
      std::cout << "motion: not found (fewer than " << params.motion.min_inliers << " consistent matches)\n";
    }

    if (gt) {
      const auto p1 = f1.points(), p2 = f2.points();
      int correct = 0, correct_inliers = 0;
      for (size_t i = 0; i < matches.size(); ++i) {
        const cv::Point3f& a = p1[static_cast<size_t>(matches[i].trainIdx)];
        const cv::Point3f& b = p2[static_cast<size_t>(matches[i].queryIdx)];
        const bool ok = (Eigen::Vector3d(a.x, a.y, a.z) - *gt * Eigen::Vector3d(b.x, b.y, b.z)).norm() <= 0.05;
        correct += ok;
        correct_inliers += ok && motion.inliers[i];
      }
      std::cout << "ground truth: " << correct << " of " << matches.size() << " matches correct (<= 5 cm), "
                << correct_inliers << " of " << motion.num_inliers << " inliers correct\n";
      if (motion.valid) {
        std::cout << "motion error: " << describeMotion(gt->inverse() * motion.train_T_query) << "\n";
      }
    }

    if (args.has("overlay")) {
      std::ostringstream caption;
      caption << "RISAS  " << f1.keypoints.size() << " / " << f2.keypoints.size() << " features  "
              << matches.size() << " matches  " << motion.num_inliers << " inliers";
      const cv::Mat overlay = risas::drawMatchOverlay(frame1.gray(), f1.keypoints, frame2.gray(), f2.keypoints,
                                                      matches, motion.inliers, caption.str());
      risas::writeImage(args.get("overlay"), overlay, "overlay");
      std::cout << "overlay written to " << args.get("overlay") << "\n";
    }
    std::cout << "summary: " << f1.keypoints.size() << " + " << f2.keypoints.size() << " features, "
              << matches.size() << " matches, " << motion.num_inliers << " inliers"
              << (motion.valid ? ", " + describeMotion(motion.train_T_query) : ", no motion") << "\n";
    return 0;
  });
}

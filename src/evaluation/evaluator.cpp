#include "risas/evaluation/evaluator.hpp"

#include "risas/errors.hpp"
#include "risas/io.hpp"

#include <chrono>
#include <functional>
#include <cmath>

namespace risas::eval {

Evaluator::Evaluator(std::vector<std::unique_ptr<FeatureMethod>> methods, const Intrinsics& intrinsics, double d_min,
                     double report_ratio, int ransac_seeds, PoseRefit refit, const ImageNoise& noise)
    : methods_(std::move(methods)),
      intrinsics_(intrinsics),
      d_min_(d_min),
      report_ratio_(report_ratio),
      ransac_seeds_(ransac_seeds),
      refit_(refit),
      noise_(noise) {
  if (ransac_seeds < 1) throw InputError("ransac_seeds must be at least 1, got " + std::to_string(ransac_seeds));
  noise.validate();
}

Evaluator::Processed Evaluator::process(const FeatureMethod& method, const LoadedFrame& frame) {
  const auto start = std::chrono::steady_clock::now();
  Processed p{method.run(frame.frame, frame.bgr), 0.0};
  p.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return p;
}

namespace {

// Keeps the keypoints with a 3D point; returns how many were dropped.
int keepWithDepth(const MethodOutput& out, const std::function<cv::Point3f(const cv::Point2f&)>& point_of,
                  std::vector<cv::Point3f>& points, cv::Mat& descriptors, std::vector<cv::Point2f>* pixels = nullptr) {
  int dropped = 0;
  descriptors = cv::Mat(0, out.descriptors.cols, out.descriptors.type());
  for (size_t i = 0; i < out.pixels.size(); ++i) {
    const cv::Point3f p = point_of(out.pixels[i]);
    if (std::isnan(p.z)) {
      ++dropped;
      continue;
    }
    points.push_back(p);
    if (pixels) pixels->push_back(out.pixels[i]);
    descriptors.push_back(out.descriptors.row(static_cast<int>(i)));
  }
  return dropped;
}

}  // namespace

Evaluator::LoadedFrame Evaluator::load(const FramePaths& paths) const {
  RgbdImages images = readRgbdImages(paths.rgb, paths.depth);
  if (noise_.sigma > 0.0) {
    images.bgr = withImageNoise(images.bgr, noise_.sigma, noise_.seed, imageNoiseIndex(paths.noiseKey()));
  }
  return {images.bgr, rgbdFrameOf(images, intrinsics_, paths.depth_units_per_metre)};
}

bool missPreferredByDepth(const PoseRecovery& pose, double agreement, double truth_agreement) {
  // NaN agreements compare false: no check, no preference.
  return pose.estimated && !pose.recovered() && agreement >= truth_agreement + kDepthPreference;
}

PoseShares poseShares(const std::vector<PoseRecovery>& poses, const std::vector<double>& agreements,
                      double truth_agreement) {
  CV_Assert(!poses.empty() && agreements.size() == poses.size());
  PoseShares shares;
  for (size_t k = 0; k < poses.size(); ++k) {
    shares.recovered += poses[k].recovered();
    shares.recovered_closely += poses[k].recoveredClosely();
    shares.missed_preferred_by_depth += missPreferredByDepth(poses[k], agreements[k], truth_agreement);
  }
  for (double* share : {&shares.recovered, &shares.recovered_closely, &shares.missed_preferred_by_depth}) {
    *share /= static_cast<double>(poses.size());
  }
  return shares;
}

std::vector<PairResult> Evaluator::evaluate(const Pair& pair) {
  const LoadedFrame reference_frame = load(pair.reference), query_frame = load(pair.query);
  const cv::Mat& reference_depth = reference_frame.frame.depth();
  const cv::Mat& query_depth = query_frame.frame.depth();
  // A rotated image's depth is the reference's: nothing to check there.
  const bool depth_checkable = pair.image_rotation_deg == 0.0;
  const double truth_agreement =
      depth_checkable ? depthAgreement(query_depth, reference_depth, intrinsics_, pair.ref_T_query) : NAN;
  // Every method's poses judged on the same points. A rotated image's
  // points are the unrotated frame's (its keypoints take that depth, and
  // ref_T_query is the identity).
  const std::vector<cv::Point3f> judged_points =
      sharedScene(depth_checkable ? query_depth : reference_depth, reference_depth, intrinsics_, pair.ref_T_query);
  std::vector<PairResult> results;
  for (const auto& method : methods_) {
    const auto key = std::make_pair(method->name(), pair.reference.rgb);
    auto cached = reference_cache_.find(key);
    if (cached == reference_cache_.end()) cached = reference_cache_.emplace(key, process(*method, reference_frame)).first;
    const Processed& reference = cached->second;
    const Processed query = process(*method, query_frame);

    PairResult r;
    r.pair = pair;
    r.method = method->name();
    r.ms_per_frame = 0.5 * (reference.ms + query.ms);
    std::vector<cv::Point3f> reference_points, query_points;
    std::vector<cv::Point2f> reference_pixels, query_pixels;
    cv::Mat reference_descriptors, query_descriptors;
    r.dropped_reference = keepWithDepth(
        reference.output, [&](const cv::Point2f& px) { return keypointPoint(reference_depth, intrinsics_, px); },
        reference_points, reference_descriptors, &reference_pixels);
    r.dropped_query = keepWithDepth(
        query.output,
        [&](const cv::Point2f& px) {
          // A rotated image's pixel takes the unrotated frame's depth there.
          return pair.image_rotation_deg != 0.0
                     ? keypointPoint(reference_depth, intrinsics_, unrotatePixel(px, pair.image_rotation_deg))
                     : keypointPoint(query_depth, intrinsics_, px);
        },
        query_points, query_descriptors, &query_pixels);
    r.reference_keypoints = static_cast<int>(reference_points.size());
    r.query_keypoints = static_cast<int>(query_points.size());
    r.repeatability = detectorRepeatability(query_points, reference_pixels, reference_depth, intrinsics_, pair.ref_T_query);
    r.positives = countPositives(query_points, reference_points, pair.ref_T_query, d_min_);
    r.candidates = nearestNeighbourCandidates(query_descriptors, reference_descriptors, method->norm(), query_points,
                                              reference_points, pair.ref_T_query, d_min_);
    const std::vector<PrPoint> curve = prCurve(r.candidates, r.positives);
    r.auc = prAuc(curve);
    r.at_ratio = atThreshold(curve, report_ratio_);
    r.distinct_correct = distinctCorrectMatches(r.candidates, query_pixels, reference_pixels, report_ratio_);
    const std::vector<PoseRecovery> poses = recoverPoseOverSeeds(
        r.candidates, report_ratio_, query_points, reference_points, pair.ref_T_query, judged_points, ransac_seeds_, refit_);
    // The depth check: the first seed's pose, reported, and every miss.
    std::vector<double> agreements;
    for (size_t k = 0; k < poses.size(); ++k) {
      const bool checked = depth_checkable && poses[k].estimated && (k == 0 || !poses[k].recovered());
      agreements.push_back(checked ? depthAgreement(query_depth, reference_depth, intrinsics_, poses[k].estimate) : NAN);
    }
    r.pose = poses.front();
    r.depth_agreement = agreements.front();
    r.depth_agreement_truth = truth_agreement;
    r.shares = poseShares(poses, agreements, truth_agreement);
    results.push_back(std::move(r));
  }
  return results;
}

}  // namespace risas::eval

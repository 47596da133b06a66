// The matching metrics of paper IV-A, made exact (see docs/evaluation.md):
// nearest-neighbour distance ratio matching of each query descriptor against
// the reference frame, correctness by 3D distance under the ground truth,
// precision-recall by sweeping the ratio threshold, and its area.
#pragma once

#include "risas/intrinsics.hpp"

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <optional>
#include <vector>

namespace risas::eval {

// One query keypoint's nearest reference neighbour: its distance ratio
// d1/d2 and whether it is a correct match.
struct Candidate {
  double ratio;
  bool correct;
  int query = -1, reference = -1;  // the rows matched
};

// A match (query i -> reference j) is correct when
// ||p_ref[j] - (R p_query[i] + t)|| <= d_min (paper eq. 9, d_min = 0.05 m).
bool isCorrect(const cv::Point3f& reference, const cv::Point3f& query, const Eigen::Isometry3d& ref_T_query,
               double d_min);

// The nearest and second-nearest reference descriptor of every query row
// under `norm` (cv::NORM_L2, NORM_HAMMING, ...). Rows without a second
// neighbour (a reference set of one) have no ratio and are left out.
std::vector<Candidate> nearestNeighbourCandidates(const cv::Mat& query, const cv::Mat& reference, int norm,
                                                  const std::vector<cv::Point3f>& query_points,
                                                  const std::vector<cv::Point3f>& reference_points,
                                                  const Eigen::Isometry3d& ref_T_query, double d_min);

// Query keypoints with a correct counterpart among the reference keypoints:
// the recall's denominator.
int countPositives(const std::vector<cv::Point3f>& query_points, const std::vector<cv::Point3f>& reference_points,
                   const Eigen::Isometry3d& ref_T_query, double d_min);

// A query-frame point moved by ref_T_query into the reference camera and
// projected there: its pixel, its depth along the reference view, and the
// reference depth at the nearest pixel (NaN where the reference has none).
// Nothing when it lies behind the camera or outside the image.
struct Landing {
  double u, v;         // reference pixel
  double depth;        // of the moved point, metres
  float depth_there;   // the reference depth image at (round(u), round(v))
};
std::optional<Landing> landInReference(const Eigen::Vector3d& query_point, const Eigen::Isometry3d& ref_T_query,
                                       const Intrinsics& K, const cv::Mat& reference_depth_metres);

// Detector repeatability under the ground truth: of the query keypoints
// whose 3D point, moved into the reference camera by ref_T_query, projects
// inside the reference image in front of it and agrees with the reference
// depth there within depth_tolerance metres (seen by both cameras, not
// occluded), the fraction with a reference keypoint within
// pixel_tolerance pixels of the projection.
// Keypoints this near each other (pixels) are one image point: the
// repeatability's tolerance, and the distinct count's.
constexpr double kSamePointPixels = 3.0;

struct Repeatability {
  int visible = 0;
  int repeated = 0;
  double rate() const { return visible ? static_cast<double>(repeated) / visible : 0.0; }
};
Repeatability detectorRepeatability(const std::vector<cv::Point3f>& query_points,
                                    const std::vector<cv::Point2f>& reference_pixels,
                                    const cv::Mat& reference_depth_metres, const Intrinsics& intrinsics,
                                    const Eigen::Isometry3d& ref_T_query, double pixel_tolerance = kSamePointPixels,
                                    double depth_tolerance = 0.05);

// The correct matches with ratio <= threshold, each image point counted
// once: taken in ascending ratio, a correct match counts unless its query
// keypoint or its reference keypoint lies within pixel_tolerance of one
// that counted already. A detector that reports one corner at several
// pyramid levels (ORB's 1000 keypoints are about 340 points 3 px apart on
// the dataset) gets a correct match per copy, and the copies tell RANSAC
// no more than one point does (docs/evaluation.md, "Correct matches, each
// image point once"). query_pixels and reference_pixels are indexed by the
// candidates' rows.
int distinctCorrectMatches(const std::vector<Candidate>& candidates, const std::vector<cv::Point2f>& query_pixels,
                           const std::vector<cv::Point2f>& reference_pixels, double threshold,
                           double pixel_tolerance = kSamePointPixels);

// The strongest keypoint of each image point: taken by descending
// response (ties in their order), a keypoint within pixel_tolerance of one
// kept is dropped. ORB made to report each corner once, before it
// describes, so that its copies neither count as correct matches nor fail
// each other's ratio test (the methods "ORB-distinct" and
// "ORB-distinct+RISAS"; docs/evaluation.md, "ORB's keypoints one per image
// point").
std::vector<cv::KeyPoint> onePerImagePoint(std::vector<cv::KeyPoint> keypoints,
                                           double pixel_tolerance = kSamePointPixels);

struct PrPoint {
  double ratio;      // threshold: matches with d1/d2 <= ratio
  double precision;  // correct / matches
  double recall;     // correct / positives
  int matches;
  int correct;
};

// One point per distinct ratio, ascending: the whole curve of thresholds in (0, 1].
std::vector<PrPoint> prCurve(std::vector<Candidate> candidates, int positives);

// Area under precision(recall), as average precision: the sum over the curve
// of the recall gained times the precision there. 0 without positives.
double prAuc(const std::vector<PrPoint>& curve);

// The curve's state at a threshold (the last point with ratio <= threshold).
PrPoint atThreshold(const std::vector<PrPoint>& curve, double threshold);

}  // namespace risas::eval

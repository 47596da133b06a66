// The evaluation protocol over a dataset in the ManipulatorsDataset layout
// (see its README): which pairs each sequence contributes, their ground
// truth, and how a keypoint becomes a 3D point.
#pragma once

#include "risas/intrinsics.hpp"
#include "risas/io.hpp"
#include "risas/tum_sequence.hpp"

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace risas::eval {

struct FramePaths {
  std::string rgb;
  std::string depth;
  double depth_units_per_metre = kMillimetreDepthUnits;  // the dataset's; TUM: 5000
  // The colour image's path under the dataset's root or the TUM folder
  // ("texture/viewchange/rgb_3.png", "rgb/1305031102.175304.png"): the
  // same wherever the data lies, which drawn noise is keyed on (Evaluator).
  std::string name;
  // What the noise is keyed on: the name, or the colour image's path where
  // there is no name (a frame listed by hand), so that no two images share
  // one draw.
  const std::string& noiseKey() const { return name.empty() ? rgb : name; }
};

// Reference frame 1 against a query frame. For synthetic_rotate the query is
// frame N turned on screen by `image_rotation_deg` counter-clockwise about
// (319.5, 239.5): a query pixel is mapped back into frame N and takes frame
// N's depth, so ref_T_query is the identity.
struct Pair {
  std::string scene;     // texture, geometry
  std::string sequence;  // viewchange, rotate, scale, illum, synthetic_rotate
  std::string label;     // the query's name: "5", "square", "rotate90"
  int step = 0;          // k of frame k (scale: the 0.1 m step), or the angle
  FramePaths reference, query;
  Eigen::Isometry3d ref_T_query = Eigen::Isometry3d::Identity();  // p_ref = R p_query + t
  double image_rotation_deg = 0.0;
};

// The sequences with ground truth, in the paper's order.
const std::vector<std::string>& evaluatedSequences();

// Which of a sequence's poses are its ground truth. Corrected: corrected/
// where the sequence has it, as the dataset's README says (its raw rotate and
// scale poses are off by more than the 5 cm threshold under the dataset's
// camera-intrinsics.txt). Raw: the arm's R1-k.txt/T1-k.txt always, which
// agree with the images under intrinsics fitted to the recordings
// (docs/evaluation.md, "The dataset's intrinsics").
enum class GroundTruthPoses { Corrected, Raw };

// All pairs of the given scene types and sequences under `root` that exist
// on disk, with the poses `poses` chooses (a sequence without corrected/
// gives its raw poses either way). InputError when a pose file is
// unreadable.
std::vector<Pair> listPairs(const std::string& root, const std::vector<std::string>& scenes,
                            const std::vector<std::string>& sequences,
                            GroundTruthPoses poses = GroundTruthPoses::Corrected);

// Pairs (frame i, frame i + gap) of the TUM RGB-D folder `dir`, as
// readTumSequence read it into `sequence`, for each gap, i = 0, stride,
// 2 stride, ...; both frames need a ground-truth pose, and ref_T_query =
// world_T_i^-1 world_T_{i+gap}. scene is the folder's name, sequence
// "gap<d>", label "i+d" (frame indices from 0 in the associated sequence),
// step the gap. InputError when a gap or the stride is not positive.
std::vector<Pair> listTumPairs(const std::string& dir, const TumSequence& sequence, const std::vector<int>& gaps,
                               int stride = 1);

// A keypoint's 3D point: the median of the valid depths in its 3x3
// neighbourhood, back-projected; NaN when none is valid. Of an even count
// the upper middle one, not the mean of the two: a depth measured there,
// never a point between the two sides of a depth jump.
cv::Point3f keypointPoint(const cv::Mat& depth_metres, const Intrinsics& K, const cv::Point2f& pixel);

// Where a pixel of the rotated query lies in the unrotated frame.
cv::Point2f unrotatePixel(const cv::Point2f& pixel, double rotation_deg, const cv::Point2f& centre = {319.5f, 239.5f});

}  // namespace risas::eval

// Sequences in the TUM RGB-D benchmark's layout (Sturm et al., IROS 2012),
// the format RGB-D odometry is scored on:
//   rgb.txt, depth.txt   "timestamp filename" lines, '#' lines are comments
//   groundtruth.txt      "timestamp tx ty tz qx qy qz qw": the colour
//                        camera's optical frame in the world (optional)
//   depth/*.png          16-bit, kTumDepthUnitsPerMetre units per metre
#pragma once

#include "risas/intrinsics.hpp"
#include "risas/rgbd_frame.hpp"

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

namespace risas {

constexpr double kTumDepthUnitsPerMetre = 5000.0;
constexpr double kTumMaxDifference = 0.02;  // associate.py's tolerance, seconds

struct TumFrame {
  double stamp = 0.0;        // the colour image's
  std::string rgb, depth;    // paths
  double depth_stamp = 0.0;
  // world_T_camera at the nearest ground-truth stamp, when one lies within
  // the association's tolerance.
  std::optional<Eigen::Isometry3d> world_T_camera;
};

// A pose at a time stamp: one line of a TUM trajectory file.
struct StampedPose {
  double stamp;
  Eigen::Isometry3d world_T_camera;
};

struct TumSequence {
  std::vector<TumFrame> frames;  // colour stamps ascending
  int unmatched_rgb = 0;         // colour images left without a depth image
  int unmatched_depth = 0;
  int without_pose = 0;          // frames with no ground truth near them
  // groundtruth.txt's poses in the file's order, the truth offset added to
  // their stamps: what the frames' poses were taken from, for a tool that
  // scores a trajectory against them (eval::associate), so that the file is
  // read, and its stamps shifted, once.
  std::vector<StampedPose> ground_truth;
  bool has_ground_truth = false;  // groundtruth.txt has a pose
  double max_difference = 0.0;    // the association's tolerance, seconds
};

// What the association left out, as one sentence for a tool to print, or ""
// when nothing was: colour images without a depth image, depth images
// without a colour image, frames without a ground-truth pose (when there is
// a ground truth). A recording whose depth stamps lag more than the
// tolerance would otherwise lose most of its frames in silence.
std::string leftOutOf(const TumSequence& sequence);

// A frame's images: colour (BGR) and depth in metres (CV_32FC1, 0 where
// missing), read as readRgbdImages reads them and scaled by
// kTumDepthUnitsPerMetre. loadTumFrame makes them an RgbdFrame
// (loadRgbdFrame): its InputError names the frame's two files, so that a
// recording's one frame whose depth has no valid pixel is found by name.
struct TumImages {
  cv::Mat bgr, depth_metres;
};
TumImages readTumImages(const TumFrame& frame);
RgbdFrame loadTumFrame(const TumFrame& frame, const Intrinsics& intrinsics);

// A file of "timestamp tx ty tz qx qy qz qw" lines ('#' lines are
// comments; quaternions are normalised): groundtruth.txt, or an estimate.
// InputError naming the file and line when unreadable or malformed.
std::vector<StampedPose> readTumTrajectory(const std::string& path);
void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses);

// Reads the folder: colour and depth paired as the benchmark's associate.py
// does (closest stamps first, each used once, |difference| < max_difference
// seconds), each pair given the pose at the nearest ground-truth stamp if it
// is within max_difference too, after truth_offset seconds are added to the
// ground truth's stamps (a motion capture whose clock is off the camera's).
// groundtruth.txt may be absent (no poses).
// InputError naming the file and line for a missing rgb.txt or depth.txt, a
// malformed or non-finite line, a listed image that does not exist, no
// pair at all, or a truth_offset that is not finite.
TumSequence readTumSequence(const std::string& dir, double max_difference = kTumMaxDifference,
                            double truth_offset = 0.0);

// The stamp pairs (index into a, index into b) associate.py would make:
// candidates with |a - b| < max_difference, closest first, each index used
// once; sorted by a's index.
std::vector<std::pair<size_t, size_t>> associateStamps(const std::vector<double>& a, const std::vector<double>& b,
                                                       double max_difference);

}  // namespace risas

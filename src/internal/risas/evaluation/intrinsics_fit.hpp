// The camera matrix a recording's own matches ask for: the intrinsics under
// which matched pixels, back-projected with their depth, move rigidly from
// one frame to the other.
//
// A wrong principal point shears every back-projected point by (Δc / f) z,
// and both frames of a pair are sheared in their own axes, so a roll θ
// between them moves each point by 2 sin(θ/2) |Δc| / f · z more than the
// motion does: points at different depths by different amounts, which no
// rigid motion absorbs. Rolls therefore pin the principal point; a wrong
// focal length scales x and y against z, which rolls barely see, so f is
// pinned loosely, by tilts (docs/evaluation.md, "The dataset's intrinsics").
#pragma once

#include "risas/intrinsics.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace risas::eval {

// One pair of frames' matches: pixel and depth (metres, > 0) in each frame.
struct DepthMatches {
  std::vector<cv::Point2f> reference_pixels, query_pixels;
  std::vector<float> reference_depths, query_depths;
};

// How far the matches of `pairs` are from moving rigidly under `intrinsics`:
// each pair's motion from RANSAC (3 cm, fixed seed) and its Umeyama refit,
// then the mean over its matches of min(r², (3 cm)²), r the residual under
// that motion (truncated, so wrong matches weigh alike under any K); the
// mean over pairs. InputError when a pair's fields differ in length.
double rigidityCost(const std::vector<DepthMatches>& pairs, const Intrinsics& intrinsics);

// The matches of `pairs` within `metres` of their pair's RANSAC motion under
// `intrinsics`: how many of them move rigidly.
int rigidMatches(const std::vector<DepthMatches>& pairs, const Intrinsics& intrinsics, double metres);

struct IntrinsicsFit {
  Intrinsics intrinsics;
  double cost_before = 0.0, cost_after = 0.0;  // rigidityCost at the start and at the fit
};

// Minimises rigidityCost over fx, fy, cx, cy from `start`: the principal
// point scanned over start ± 96 px in steps of 8 px (the cost is jagged, and
// a descent alone can stop tens of pixels short), then coordinate descent
// from the best, each parameter tried 16 px either way, the steps halved
// when none lowers the cost, down to a quarter pixel. Deterministic.
// InputError when `start` is not valid or no pair has the matches a rigid
// motion needs (6).
IntrinsicsFit fitIntrinsics(const std::vector<DepthMatches>& pairs, const Intrinsics& start);

}  // namespace risas::eval

// risas_fit_intrinsics: the camera matrix under which a recording's matches
// move rigidly (evaluation/intrinsics_fit.hpp), from SIFT's matches between
// frame 1 and every other frame of sequences in the ManipulatorsDataset
// layout. SIFT, not RISAS or ORB: the intrinsics then judge the methods the
// evaluation compares without having been fitted to any of them.
#include "cli.hpp"

#include "risas/errors.hpp"
#include "risas/evaluation/intrinsics_fit.hpp"
#include "risas/evaluation/methods.hpp"
#include "risas/evaluation/protocol.hpp"
#include "risas/io.hpp"
#include "risas/matcher.hpp"

#include <opencv2/core/utility.hpp>

#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace {

// SIFT's matches (ratio 0.8) of frame k against frame 1, each keypoint at
// the median depth of its 3x3 pixels (the evaluation's keypointPoint);
// matches without depth in either frame are left out.
risas::eval::DepthMatches siftMatches(const risas::eval::FeatureMethod& sift, const risas::RgbdFrame& reference,
                                      const risas::eval::MethodOutput& reference_features,
                                      const risas::RgbdFrame& query) {
  const risas::eval::MethodOutput query_features = sift.run(query, cv::Mat());
  risas::eval::DepthMatches out;
  if (reference_features.descriptors.empty() || query_features.descriptors.empty()) return out;
  for (const cv::DMatch& m : risas::matchDescriptors(query_features.descriptors, reference_features.descriptors)) {
    const cv::Point2f a = reference_features.pixels[static_cast<size_t>(m.trainIdx)];
    const cv::Point2f b = query_features.pixels[static_cast<size_t>(m.queryIdx)];
    const float za = risas::eval::keypointPoint(reference.depth(), reference.intrinsics(), a).z;
    const float zb = risas::eval::keypointPoint(query.depth(), query.intrinsics(), b).z;
    if (!(za > 0.0f) || !(zb > 0.0f)) continue;
    out.reference_pixels.push_back(a);
    out.query_pixels.push_back(b);
    out.reference_depths.push_back(za);
    out.query_depths.push_back(zb);
  }
  return out;
}

std::string matrixText(const risas::Intrinsics& K) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(2) << K.fx << " 0 " << K.cx << "\n0 " << K.fy << " " << K.cy << "\n0 0 1\n";
  return text.str();
}

}  // namespace

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_fit_intrinsics", [&] {
    std::vector<risas::cli::Option> options = {
        {"data", "LIST", "sequence folders (rgb_k.png, depth_k.png in millimetres), comma-separated"},
        {"out", "K.txt", "write the fitted camera matrix there, as camera-intrinsics.txt"}};
    for (const risas::cli::Option& o : risas::cli::intrinsicsOptions()) options.push_back(o);
    const risas::cli::Args args(
        argc, argv,
        "risas_fit_intrinsics --data SEQ_DIR[,SEQ_DIR...] [--intrinsics K.txt | --fx F --fy F --cx C --cy C] [--out K.txt]\n"
        "Fits fx, fy, cx, cy so that SIFT's matches between frame 1 and each other frame of the\n"
        "sequences, back-projected with their depth, move rigidly: a wrong principal point bends\n"
        "them in every pair the camera rolls between. Starts from the given intrinsics, else from\n"
        "the camera-intrinsics.txt at or above the first sequence. Prints, per pair and in all,\n"
        "the matches within 1 cm of their pair's RANSAC motion under the start and under the fit.",
        options);
    cv::setNumThreads(1);
    if (!args.has("data")) throw risas::cli::UsageError("give --data SEQ_DIR[,SEQ_DIR...]");
    const std::vector<std::string> sequences = args.getList("data", "");
    const risas::Intrinsics start = risas::cli::intrinsicsGivenOrFound(args, sequences.front());
    if (args.has("out")) risas::cli::requireWritable(args.get("out"));

    const auto sift = risas::eval::makeMethod("SIFT", risas::RisasParams());
    std::vector<risas::eval::DepthMatches> pairs;
    std::vector<std::string> names;
    for (const std::string& dir : sequences) {
      const std::vector<risas::SequenceFrame> frames = risas::listSequence(dir);
      if (frames.size() < 2) throw risas::InputError(dir + ": fewer than two frames (rgb_k.png, depth_k.png)");
      const risas::RgbdFrame reference = risas::loadRgbdFrame(frames[0].rgb_path, frames[0].depth_path, start);
      const risas::eval::MethodOutput reference_features = sift->run(reference, cv::Mat());
      for (size_t k = 1; k < frames.size(); ++k) {
        pairs.push_back(siftMatches(*sift, reference, reference_features,
                                    risas::loadRgbdFrame(frames[k].rgb_path, frames[k].depth_path, start)));
        names.push_back(dir + " 1-" + std::to_string(frames[k].index));
      }
    }
    const risas::eval::IntrinsicsFit fit = risas::eval::fitIntrinsics(pairs, start);
    constexpr double kRigid = 0.01;  // metres
    for (size_t i = 0; i < pairs.size(); ++i) {
      std::cout << names[i] << ": " << pairs[i].reference_pixels.size() << " matches, within 1 cm "
                << risas::eval::rigidMatches({pairs[i]}, start, kRigid) << " -> "
                << risas::eval::rigidMatches({pairs[i]}, fit.intrinsics, kRigid) << "\n";
    }
    std::cout << "start:  fx " << start.fx << " fy " << start.fy << " cx " << start.cx << " cy " << start.cy
              << ", cost " << fit.cost_before << ", within 1 cm " << risas::eval::rigidMatches(pairs, start, kRigid)
              << "\nfitted: fx " << fit.intrinsics.fx << " fy " << fit.intrinsics.fy << " cx " << fit.intrinsics.cx
              << " cy " << fit.intrinsics.cy << ", cost " << fit.cost_after << ", within 1 cm "
              << risas::eval::rigidMatches(pairs, fit.intrinsics, kRigid) << "\n";
    if (args.has("out")) {
      std::ofstream out(args.get("out"));
      out << matrixText(fit.intrinsics);
      if (!out.flush()) throw risas::InputError("cannot write " + args.get("out"));
      std::cout << "written to " << args.get("out") << "\n";
    }
    return 0;
  });
}

// risas_fit_intrinsics: the camera matrix under which a recording's matches
// move rigidly (evaluation/intrinsics_fit.hpp), from SIFT's matches between
// frame 1 and every other frame of sequences in the ManipulatorsDataset
// layout, or between frames i and i + gap of a TUM RGB-D folder. SIFT, not
// RISAS or ORB: the intrinsics then judge the methods the evaluation
// compares without having been fitted to any of them.
#include "cli.hpp"

#include "risas/errors.hpp"
#include "risas/evaluation/intrinsics_fit.hpp"
#include "risas/evaluation/methods.hpp"
#include "risas/evaluation/protocol.hpp"
#include "risas/io.hpp"
#include "risas/matcher.hpp"
#include "risas/tum_sequence.hpp"

#include <opencv2/core/utility.hpp>

#include <iostream>

namespace {

// SIFT's matches (ratio 0.8) of the query frame against the reference, each
// keypoint at the median depth of its 3x3 pixels (the evaluation's
// keypointPoint); matches without depth in either frame are left out.
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

}  // namespace

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_fit_intrinsics", [&] {
    std::vector<risas::cli::Option> options = {
        {"data", "LIST", "sequence folders (rgb_k.png, depth_k.png in millimetres), comma-separated: pairs (1, k)"},
        {"tum", "DIR", "instead of --data: a TUM RGB-D folder (rgb.txt, depth.txt; depth at 5000 a metre): pairs (i, i+gap)"},
        {"gap", "N", "with --tum: frames between a pair's two (default: 1)"},
        {"pair-stride", "N", "with --tum: pairs start at every N-th frame (default: 1)"},
        {"out", "K.txt", "write the fitted camera matrix there, as camera-intrinsics.txt"}};
    for (const risas::cli::Option& o : risas::cli::intrinsicsOptions()) options.push_back(o);
    const risas::cli::Args args(
        argc, argv,
        "risas_fit_intrinsics --data SEQ_DIR[,SEQ_DIR...] [--intrinsics K.txt | --fx F --fy F --cx C --cy C] [--out K.txt]\n"
        "risas_fit_intrinsics --tum TUM_DIR --intrinsics K.txt | --fx F --fy F --cx C --cy C [--gap N] [--pair-stride N]\n"
        "                     [--out K.txt]\n"
        "Fits fx, fy, cx, cy so that SIFT's matches between the two frames of each pair, back-\n"
        "projected with their depth, move rigidly: a wrong principal point bends them in every\n"
        "pair the camera rolls between. Starts from the given intrinsics, else (--data) from the\n"
        "camera-intrinsics.txt at or above the first sequence. Prints, per pair and in all, the\n"
        "matches within 1 cm of their pair's RANSAC motion under the start and under the fit.",
        options);
    cv::setNumThreads(1);
    const bool tum = args.has("tum");
    if (tum == args.has("data")) throw risas::cli::UsageError("give either --data SEQ_DIR[,SEQ_DIR...] or --tum TUM_DIR");
    if (!tum) args.refuse({"gap", "pair-stride"}, "with --data");
    const int gap = args.getInt("gap", 1, 1, 1000000), stride = args.getInt("pair-stride", 1, 1, 1000000);
    const std::vector<std::string> sequences = tum ? std::vector<std::string>{args.get("tum")} : args.getList("data", "");
    const risas::Intrinsics start =
        tum ? risas::cli::intrinsicsFrom(args) : risas::cli::intrinsicsGivenOrFound(args, sequences.front());
    if (args.has("out")) risas::cli::requireWritable(args.get("out"));

    // The pairs, each named by its sequence and frames.
    std::vector<std::pair<risas::eval::FramePaths, risas::eval::FramePaths>> frame_pairs;
    std::vector<std::string> names;
    if (tum) {
      const risas::TumSequence sequence = risas::cli::readTumSequenceNoting("risas_fit_intrinsics", sequences.front());
      const auto& frames = sequence.frames;
      for (size_t i = 0; i + static_cast<size_t>(gap) < frames.size(); i += static_cast<size_t>(stride)) {
        const risas::TumFrame &a = frames[i], &b = frames[i + static_cast<size_t>(gap)];
        frame_pairs.push_back({{a.rgb, a.depth, risas::kTumDepthUnitsPerMetre}, {b.rgb, b.depth, risas::kTumDepthUnitsPerMetre}});
        names.push_back(sequences.front() + " " + std::to_string(i) + "+" + std::to_string(gap));
      }
    } else {
      for (const std::string& dir : sequences) {
        const std::vector<risas::SequenceFrame> frames = risas::listSequence(dir);
        if (frames.size() < 2) throw risas::InputError(dir + ": fewer than two frames (rgb_k.png, depth_k.png)");
        for (size_t k = 1; k < frames.size(); ++k) {
          frame_pairs.push_back({{frames[0].rgb_path, frames[0].depth_path}, {frames[k].rgb_path, frames[k].depth_path}});
          names.push_back(dir + " 1-" + std::to_string(frames[k].index));
        }
      }
    }
    if (frame_pairs.empty()) throw risas::InputError(sequences.front() + ": no pair of frames " + std::to_string(gap) + " apart");

    const auto sift = risas::eval::makeMethod("SIFT", risas::RisasParams());
    const auto load = [&](const risas::eval::FramePaths& f) {
      return risas::loadRgbdFrame(f.rgb, f.depth, start, f.depth_units_per_metre);
    };
    std::vector<risas::eval::DepthMatches> pairs;
    std::string reference_path;  // the last reference described: --data's frame 1 once a sequence
    risas::RgbdFrame reference;
    risas::eval::MethodOutput reference_features;
    for (const auto& [reference_frame, query_frame] : frame_pairs) {
      if (reference_frame.rgb != reference_path) {
        reference = load(reference_frame);
        reference_features = sift->run(reference, cv::Mat());
        reference_path = reference_frame.rgb;
      }
      pairs.push_back(siftMatches(*sift, reference, reference_features, load(query_frame)));
    }
    const risas::eval::IntrinsicsFit fit = risas::eval::fitIntrinsics(pairs, start);
    constexpr double kRigid = 0.01;  // metres
    int rigid_before = 0, rigid_after = 0;
    for (size_t i = 0; i < pairs.size(); ++i) {
      const int before = risas::eval::rigidMatches({pairs[i]}, start, kRigid);
      const int after = risas::eval::rigidMatches({pairs[i]}, fit.intrinsics, kRigid);
      rigid_before += before;
      rigid_after += after;
      std::cout << names[i] << ": " << pairs[i].reference_pixels.size() << " matches, within 1 cm " << before
                << " -> " << after << "\n";
    }
    std::cout << "start:  fx " << start.fx << " fy " << start.fy << " cx " << start.cx << " cy " << start.cy
              << ", cost " << fit.cost_before << ", within 1 cm " << rigid_before << "\nfitted: fx "
              << fit.intrinsics.fx << " fy " << fit.intrinsics.fy << " cx " << fit.intrinsics.cx << " cy "
              << fit.intrinsics.cy << ", cost " << fit.cost_after << ", within 1 cm " << rigid_after << "\n";
    if (args.has("out")) {
      risas::cli::writeIntrinsicsFile(args.get("out"), fit.intrinsics);
      std::cout << "written to " << args.get("out") << "\n";
    }
    return 0;
  });
}

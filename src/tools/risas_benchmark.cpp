// risas_benchmark: ms per frame for each RISAS stage beside OpenCV ORB (1000
// features) and SIFT on the same frames in the same run.
#include "cli.hpp"

#include "risas/descriptor.hpp"
#include "risas/detector.hpp"
#include "risas/errors.hpp"
#include "risas/evaluation/median.hpp"
#include "risas/geometry.hpp"
#include "risas/io.hpp"
#include "risas/risas.hpp"
#include "risas/synthetic_scene.hpp"
#include "risas/tum_sequence.hpp"

#include <opencv2/features2d.hpp>

#include <algorithm>
#include <chrono>
#include <functional>
#include <iomanip>
#include <iostream>
#include <utility>

namespace {

std::vector<risas::RgbdFrame> loadSequence(const std::string& dir, int max_frames) {
  const risas::Intrinsics K = risas::findIntrinsics(dir);
  std::vector<risas::RgbdFrame> frames;
  for (const risas::SequenceFrame& f : risas::listSequence(dir)) {
    if (static_cast<int>(frames.size()) == max_frames) break;
    frames.push_back(risas::loadRgbdFrame(f.rgb_path, f.depth_path, K));
  }
  if (frames.empty()) throw risas::InputError("no rgb_1.png/depth_1.png in " + dir);
  return frames;
}

// `max_frames` frames spread evenly over a TUM RGB-D recording (its
// neighbouring frames are nearly the same image): the first, the last and
// those between.
std::vector<risas::RgbdFrame> loadTumSequence(const std::string& dir, const risas::Intrinsics& K, int max_frames) {
  const risas::TumSequence sequence = risas::cli::readTumSequenceNoting("risas_benchmark", dir);
  const size_t available = sequence.frames.size(), count = std::min(available, static_cast<size_t>(max_frames));
  std::vector<risas::RgbdFrame> frames;
  for (size_t i = 0; i < count; ++i) {
    const size_t index = count == 1 ? 0 : i * (available - 1) / (count - 1);
    frames.push_back(risas::loadTumFrame(sequence.frames[index], K));
  }
  return frames;
}

std::vector<risas::RgbdFrame> syntheticSequence(int count) {
  const risas::SyntheticScene scene = risas::SyntheticScene::demo();
  std::vector<risas::RgbdFrame> frames;
  for (int k = 0; k < count; ++k) {
    const risas::SyntheticRender r = scene.render(risas::syntheticIntrinsics(), cv::Size(640, 480),
                                                  risas::SyntheticScene::demoCamera(0.08 * k));
    frames.emplace_back(r.bgr, r.depth_mm, risas::syntheticIntrinsics());
  }
  return frames;
}

// Median over repeats of one call, in milliseconds.
double timeMs(int repeats, const std::function<void()>& work) {
  std::vector<double> ms;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    work();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  return risas::eval::median(std::move(ms));
}

}  // namespace

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_benchmark", [&] {
    std::vector<risas::cli::Option> options = {
        {"data", "DIR", "a sequence folder with rgb_k.png/depth_k.png (camera-intrinsics.txt in it or above)"},
        {"tum", "DIR", "instead of --data: a TUM RGB-D folder (rgb.txt, depth.txt), frames spread over it"},
        {"frames", "N", "frames to time (default 5)"},
        {"repeats", "N", "runs per frame, the median counts (default 3)"},
        {"threads", "N", "OpenCV threads (default 1: single-threaded; 0: all cores)"},
        risas::cli::paramsOption()};
    for (const risas::cli::Option& o : risas::cli::intrinsicsOptions()) options.push_back(o);
    const risas::cli::Args args(
        argc, argv,
        "risas_benchmark [--data SEQUENCE_DIR] [--frames 5] [--repeats 3] [--threads 1] [--params P.yml]\n"
        "risas_benchmark --tum TUM_DIR --intrinsics K.txt | --fx F --fy F --cx C --cy C [--frames 5] ...\n"
        "Times each RISAS stage per frame beside OpenCV ORB (1000 features) and SIFT on the\n"
        "same frames. Without --data or --tum it renders synthetic frames.",
        options);
    const int count = args.getInt("frames", 5, 1, 100000), repeats = args.getInt("repeats", 3, 1, 1000);
    const int threads = args.getInt("threads", 1, 0, 1024);
    cv::setNumThreads(threads == 0 ? -1 : threads);
    if (args.has("data") && args.has("tum")) throw risas::cli::UsageError("give --data or --tum, not both");
    if (!args.has("tum")) {
      args.refuse(risas::cli::intrinsicsOptionNames(),
                  args.has("data") ? "with --data: its camera-intrinsics.txt is read" : "to the synthetic frames");
    }
    const std::vector<risas::RgbdFrame> frames =
        args.has("tum")    ? loadTumSequence(args.get("tum"), risas::cli::intrinsicsFrom(args), count)
        : args.has("data") ? loadSequence(args.get("data"), count)
                           : syntheticSequence(count);
    const std::string source = args.has("tum") ? args.get("tum") : args.get("data", "the synthetic scene");
    const risas::RisasParams params = risas::cli::paramsFrom(args);
    const auto risas = risas::Risas::create(params);
    // The stages one by one, as Risas runs them (its inside, from the library's internal headers).
    const risas::Detector detector(params.detector);
    const risas::Descriptor descriptor(params.descriptor);
    const auto orb = cv::ORB::create(1000);
    const auto sift = cv::SIFT::create();

    double geometry_ms = 0, detector_ms = 0, descriptor_ms = 0, total_ms = 0, orb_ms = 0, sift_ms = 0;
    double risas_kp = 0, orb_kp = 0, sift_kp = 0;
    for (const risas::RgbdFrame& frame : frames) {
      risas::FrameGeometry geometry;
      std::vector<cv::KeyPoint> keypoints, described;
      cv::Mat descriptors;
      geometry_ms += timeMs(repeats, [&] { risas::computeGeometry(frame, params.geometry, geometry); });
      detector_ms += timeMs(repeats, [&] { detector.detect(frame, geometry, keypoints); });
      descriptor_ms += timeMs(repeats, [&] {
        described = keypoints;
        descriptor.compute(frame, geometry, described, descriptors);
      });
      total_ms += timeMs(repeats, [&] { risas->detectAndCompute(frame, cv::Mat(), keypoints, descriptors); });
      risas_kp += static_cast<double>(keypoints.size());
      orb_ms += timeMs(repeats, [&] { orb->detectAndCompute(frame.gray(), cv::noArray(), keypoints, descriptors); });
      orb_kp += static_cast<double>(keypoints.size());
      sift_ms += timeMs(repeats, [&] { sift->detectAndCompute(frame.gray(), cv::noArray(), keypoints, descriptors); });
      sift_kp += static_cast<double>(keypoints.size());
    }
    const double n = static_cast<double>(frames.size());
    const double orb_per_frame = orb_ms / n;
    std::cout << "risas_benchmark: " << frames.size() << " frame(s) " << frames[0].size().width << "x"
              << frames[0].size().height << " from " << source
              << ", " << cv::getNumThreads() << " thread(s), median of " << repeats << " runs, OpenCV "
              << CV_VERSION << "\n\n";
    std::cout << std::left << std::setw(26) << "stage" << std::right << std::setw(12) << "ms/frame" << std::setw(10)
              << "x ORB" << std::setw(14) << "keypoints\n";
    const auto row = [&](const std::string& name, double ms, double keypoints) {
      std::cout << std::left << std::setw(26) << name << std::right << std::fixed << std::setprecision(2)
                << std::setw(12) << ms / n << std::setw(10) << (ms / n) / orb_per_frame;
      if (keypoints >= 0) std::cout << std::setw(13) << std::setprecision(0) << keypoints / n;
      std::cout << "\n";
    };
    row("RISAS geometry (normals)", geometry_ms, -1);
    row("RISAS detector", detector_ms, -1);
    row("RISAS descriptor", descriptor_ms, -1);
    row("RISAS total", total_ms, risas_kp);
    row("OpenCV ORB (1000)", orb_ms, orb_kp);
    row("OpenCV SIFT", sift_ms, sift_kp);
    return 0;
  });
}

// risas_evaluate: the paper's evaluation (section IV) of RISAS and its peers on
// a dataset in the ManipulatorsDataset layout: PR curves, PR-AUC, precision,
// recall and correct matches at NNDR 0.8, ms per frame; CSV, markdown, plots.
#include "cli.hpp"
#include "image_noise_options.hpp"

#include "risas/errors.hpp"
#include "risas/evaluation/evaluator.hpp"
#include "risas/io.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace {

// InputError unless each of `names` is a folder under one of `parents`: a
// misspelt scene or sequence would otherwise be left out in silence.
void requireFolders(const std::string& option, const std::vector<std::filesystem::path>& parents,
                    const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    const bool found = std::any_of(parents.begin(), parents.end(), [&](const std::filesystem::path& parent) {
      return std::filesystem::is_directory(parent / name);
    });
    if (!found) {
      std::string where;
      for (const auto& parent : parents) where += (where.empty() ? "" : " or ") + parent.string();
      throw risas::InputError("--" + option + ": no folder '" + name + "' in " + where);
    }
  }
}

// The pairs the options ask for: a TUM folder's (--gaps, --pair-stride) or
// the dataset's (--scenes, --sequences, with `poses` as their ground truth),
// then those labelled in --pairs.
std::vector<risas::eval::Pair> pairsFrom(const risas::cli::Args& args, const std::string& root, bool tum,
                                         const std::string& all_sequences, risas::eval::GroundTruthPoses poses) {
  std::vector<risas::eval::Pair> pairs;
  if (tum) {
    const std::vector<int> gaps = args.getIntList("gaps", "1", 1, 1000000);
    const double truth_offset = args.getDouble("truth-offset", 0.0);
    pairs = risas::eval::listTumPairs(root, risas::cli::readTumSequenceNoting("risas_evaluate", root, truth_offset),
                                      gaps, args.getInt("pair-stride", 1, 1, 1000000));
  } else {
    const std::vector<std::string> scenes = args.getList("scenes", "texture,geometry"),
                                   sequences = args.getList("sequences", all_sequences);
    // The folders named are there; of the defaults, those there are evaluated.
    if (args.has("scenes")) requireFolders("scenes", {root}, scenes);
    if (args.has("sequences")) {
      std::vector<std::filesystem::path> scene_dirs;
      for (const std::string& scene : scenes) scene_dirs.push_back(std::filesystem::path(root) / scene);
      requireFolders("sequences", scene_dirs, sequences);
    }
    pairs = risas::eval::listPairs(root, scenes, sequences, poses);
  }
  if (args.has("pairs")) {
    const std::vector<std::string> wanted = args.getList("pairs", "");
    for (const std::string& label : wanted) {
      if (std::none_of(pairs.begin(), pairs.end(), [&](const risas::eval::Pair& p) { return p.label == label; })) {
        throw risas::InputError("--pairs: no pair is labelled '" + label + "' among those of " + root +
                                " and the other options");
      }
    }
    pairs.erase(std::remove_if(pairs.begin(), pairs.end(), [&](const risas::eval::Pair& p) {
                  return std::find(wanted.begin(), wanted.end(), p.label) == wanted.end();
                }), pairs.end());
  }
  return pairs;
}

// The paper's parameter studies as RISAS variants.
std::vector<std::unique_ptr<risas::eval::FeatureMethod>> studyMethods(const std::string& study,
                                                                      const risas::RisasParams& base) {
  std::vector<std::unique_ptr<risas::eval::FeatureMethod>> methods;
  if (study == "bins") {  // the paper's sectors, without rings
    for (int n_pie : {4, 8, 12}) {
      for (int n_bin : {8, 16}) {
        for (int n_vec : {0, 1, 2}) {  // 0: no shape labels (the default), 2: the paper's
          risas::RisasParams p = base;
          p.descriptor.n_ring = 1;
          p.descriptor.n_pie = n_pie;
          p.descriptor.n_bin = n_bin;
          p.descriptor.n_vec = n_vec;
          std::ostringstream name;
          name << "RISAS(" << n_pie << "/" << n_bin << "/" << n_vec << ")";
          methods.push_back(risas::eval::makeRisas(name.str(), p));
        }
      }
    }
  } else if (study == "layout") {  // rings against rank groups, the sectors and shape labels the base's
    for (int n_ring : {1, 2, 3}) {
      for (int n_bin : {2, 4, 6, 8}) {
        risas::RisasParams p = base;
        p.descriptor.n_ring = n_ring;
        p.descriptor.n_bin = n_bin;
        std::ostringstream name;
        name << "RISAS(n_ring=" << n_ring << "/n_bin=" << n_bin << ")";
        methods.push_back(risas::eval::makeRisas(name.str(), p));
      }
    }
  } else if (study == "tau") {
    for (double tau : {0.0, 0.2, 0.4, 0.6, 0.8, 1.0}) {
      risas::RisasParams p = base;
      p.detector.tau = tau;
      std::ostringstream name;
      name << "RISAS(tau=" << std::setprecision(1) << std::fixed << tau << ")";
      methods.push_back(risas::eval::makeRisas(name.str(), p));
    }
  } else {
    throw risas::cli::UsageError("--study is bins, layout or tau, not '" + study + "'");
  }
  return methods;
}

}  // namespace

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_evaluate", [&] {
    std::string all_methods;
    for (const std::string& m : risas::eval::methodNames()) all_methods += (all_methods.empty() ? "" : ",") + m;
    std::string all_sequences;
    for (const std::string& s : risas::eval::evaluatedSequences()) all_sequences += (all_sequences.empty() ? "" : ",") + s;
    const std::string plot_script = risas::cli::scriptPath("plot_evaluation.py");
    std::vector<risas::cli::Option> options = {
        {"data", "DIR", "dataset root: <scene>/<sequence>/rgb_k.png ..., camera-intrinsics.txt"},
        {"tum", "DIR", "instead of --data: a TUM RGB-D folder (rgb.txt, depth.txt, groundtruth.txt)"},
        {"gaps", "LIST", "with --tum: frame gaps d of the pairs (i, i+d) (default: 1)"},
        {"pair-stride", "N", "with --tum: pairs start at every N-th frame (default: 1)"},
        {"truth-offset", "S",
         "with --tum: seconds added to groundtruth.txt's stamps before each frame takes the nearest, as "
         "risas_odometry's (default: 0)"},
        {"out", "DIR", "output folder (default: evaluation)"},
        {"methods", "LIST", "methods to run (default: all of " + all_methods + ")"},
        {"scenes", "LIST", "scene types (default: texture,geometry)"},
        {"sequences", "LIST", "sequences (default: " + all_sequences + ")"},
        {"pairs", "LIST", "only these query labels, e.g. 3,5,square,rotate90"},
        {"study", "NAME", "parameter study instead of --methods: bins (n_pie x n_bin x n_vec, one ring), layout (n_ring x n_bin) or tau"},
        {"ransac-seeds", "N", "pose recovery with N RANSAC seeds, success as the share of them (default: 8)"},
        {"pose-refit", "NAME", "umeyama: the pose fitted to the inliers' 3D points (default); reprojection: then refined on their reprojection errors, as risas_odometry"},
        {"ground-truth", "NAME", "with --data: corrected: a sequence's corrected/ poses where it has them (default, the dataset's README); raw: the arm's R1-k/T1-k.txt, which agree with the images under fitted intrinsics (risas_fit_intrinsics)"},
        {"no-plots", "", "do not plot (plots with " + plot_script + ")"}};
    for (const risas::cli::Option& o : risas::cli::imageNoiseOptions("an image's is the same in every pair")) {
      options.push_back(o);
    }
    options.push_back(risas::cli::paramsOption());
    for (const risas::cli::Option& o : risas::cli::intrinsicsOptions()) options.push_back(o);
    const risas::cli::Args args(
        argc, argv,
        "risas_evaluate --data DATASET_ROOT [--out DIR] [--methods M,...] [--scenes S,...] [--sequences S,...]\n"
        "               [--pairs LABEL,...] [--study bins|layout|tau] [--ransac-seeds N] [--pose-refit umeyama|reprojection]\n"
        "               [--intrinsics K.txt | --fx F --fy F --cx C --cy C] [--ground-truth corrected|raw]\n"
        "               [--params P.yml] [--no-plots] [--image-noise SIGMA [--noise-seed N]]\n"
        "risas_evaluate --tum TUM_DIR --intrinsics K.txt | --fx F --fy F --cx C --cy C [--gaps 1,2]\n"
        "               [--pair-stride N] [--truth-offset S] [--out DIR] [--methods M,...] [--ransac-seeds N]\n"
        "               [--pose-refit umeyama|reprojection] [--params P.yml] [--no-plots]\n"
        "               [--image-noise SIGMA [--noise-seed N]]\n"
        "Reference frame against query frame: NNDR matching, a match correct when its 3D points\n"
        "agree within 5 cm under the ground truth; PR curves, PR-AUC, precision, recall and\n"
        "correct matches at ratio 0.8; the rigid motion RANSAC recovers from those matches and its\n"
        "error (success within 5 deg / 5 cm and 2 deg / 2 cm, the share of the RANSAC seeds), per\n"
        "pair, sequence and scene.\n"
        "--image-noise SIGMA evaluates the images as a noisier camera (dim light) would see them; each\n"
        "image's noise is drawn from --noise-seed and its path under the data's root.\n"
        "Writes pairs.csv, curves.csv, summary.csv, summary.md, scale.csv and PNG plots into DIR.",
        options);
    cv::setNumThreads(1);  // every method single-threaded, as the paper timed them
    const int ransac_seeds = args.getInt("ransac-seeds", 8, 1, 1000);
    const risas::eval::ImageNoise noise = risas::cli::imageNoiseFrom(args);
    const std::string refit_name = args.get("pose-refit", "umeyama");
    if (refit_name != "umeyama" && refit_name != "reprojection") {
      throw risas::cli::UsageError("--pose-refit is umeyama or reprojection, not '" + refit_name + "'");
    }
    const risas::eval::PoseRefit refit =
        refit_name == "reprojection" ? risas::eval::PoseRefit::Reprojection : risas::eval::PoseRefit::Umeyama;
    const std::string poses_name = args.get("ground-truth", "corrected");
    if (poses_name != "corrected" && poses_name != "raw") {
      throw risas::cli::UsageError("--ground-truth is corrected or raw, not '" + poses_name + "'");
    }
    const risas::eval::GroundTruthPoses poses =
        poses_name == "raw" ? risas::eval::GroundTruthPoses::Raw : risas::eval::GroundTruthPoses::Corrected;
    const bool tum = args.has("tum");
    if (tum == args.has("data")) throw risas::cli::UsageError("give either --data DATASET_ROOT or --tum TUM_DIR");
    if (tum) {
      args.refuse({"scenes", "sequences", "ground-truth"}, "with --tum");
    } else {
      args.refuse({"gaps", "pair-stride", "truth-offset"}, "with --data");
    }
    if (args.has("study")) args.refuse({"methods"}, "with --study: the study's methods are run");
    const std::string root = tum ? args.get("tum") : args.get("data"), out = args.get("out", "evaluation");
    if (!std::filesystem::is_directory(root)) throw risas::InputError("no folder " + root);
    const risas::Intrinsics intrinsics =
        tum ? risas::cli::intrinsicsFrom(args) : risas::cli::intrinsicsGivenOrFound(args, root);
    const risas::RisasParams params = risas::cli::paramsFrom(args);

    std::vector<std::unique_ptr<risas::eval::FeatureMethod>> methods;
    if (args.has("study")) {
      methods = studyMethods(args.get("study"), params);
    } else {
      for (const std::string& m : args.getList("methods", all_methods)) methods.push_back(risas::eval::makeMethod(m, params));
    }
    const std::vector<risas::eval::Pair> pairs = pairsFrom(args, root, tum, all_sequences, poses);
    if (pairs.empty()) throw risas::InputError("no pairs to evaluate under " + root + " with these filters");
    // The output folder, made and checked before hours of work, and after
    // every option and input has been checked: a typo leaves no folder.
    risas::cli::makeOutputFolder(out);
    risas::cli::requireWritable((std::filesystem::path(out) / "summary.csv").string());

    risas::eval::Evaluator evaluator(std::move(methods), intrinsics, risas::eval::kCorrectDistance,
                                     risas::eval::kReportRatio, ransac_seeds, refit, noise);
    risas::cli::noteImageNoise(noise);
    std::vector<risas::eval::PairResult> results;
    for (size_t i = 0; i < pairs.size(); ++i) {
      const risas::eval::Pair& pair = pairs[i];
      std::cout << "[" << i + 1 << "/" << pairs.size() << "] " << pair.scene << "/" << pair.sequence << " "
                << pair.label << ":" << std::flush;
      std::vector<risas::eval::PairResult> pair_results;
      try {
        pair_results = evaluator.evaluate(pair);
      } catch (...) {
        std::cout << std::endl;  // the error's line starts a line of its own
        throw;
      }
      for (risas::eval::PairResult& r : pair_results) {
        std::cout << "  " << r.method << " " << std::fixed << std::setprecision(2) << r.auc;
        results.push_back(std::move(r));
      }
      std::cout << "\n";
    }
    risas::eval::writeReports(out, results, risas::eval::kReportRatio, refit);
    std::cout << "\nPR-AUC (mean per sequence) and pose recovery; details in " << out << "/summary.csv\n\n";
    std::ifstream summary(std::filesystem::path(out) / "summary.md");
    std::cout << summary.rdbuf();

    if (!args.has("no-plots") && plot_script.empty()) {
      std::cerr << "risas_evaluate: no plots: plot_evaluation.py is neither installed nor in the source tree\n";
    } else if (!args.has("no-plots")) {
      const std::string command = plot_script + " " + out;
      if (std::system(command.c_str()) != 0) {
        std::cerr << "risas_evaluate: plotting failed (needs python3-matplotlib); run: " << command << "\n";
      }
    }
    return 0;
  });
}

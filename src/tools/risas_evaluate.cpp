// risas_evaluate: the paper's evaluation (section IV) of RISAS and its peers on
// a dataset in the ManipulatorsDataset layout: PR curves, PR-AUC, precision,
// recall and correct matches at NNDR 0.8, ms per frame; CSV, markdown, plots.
#include "cli.hpp"

#include "risas/errors.hpp"
#include "risas/evaluation/evaluator.hpp"
#include "risas/io.hpp"

#include <opencv2/core/utility.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace {

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> items;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

// The paper's parameter studies as RISAS variants.
std::vector<std::unique_ptr<risas::eval::FeatureMethod>> studyMethods(const std::string& study,
                                                                      const risas::RisasParams& base) {
  std::vector<std::unique_ptr<risas::eval::FeatureMethod>> methods;
  if (study == "bins") {
    for (int n_pie : {4, 8, 12}) {
      for (int n_bin : {8, 16}) {
        for (int n_vec : {1, 2}) {
          risas::RisasParams p = base;
          p.descriptor.n_pie = n_pie;
          p.descriptor.n_bin = n_bin;
          p.descriptor.n_vec = n_vec;
          std::ostringstream name;
          name << "RISAS(" << n_pie << "/" << n_bin << "/" << n_vec << ")";
          methods.push_back(risas::eval::makeRisas(name.str(), p));
        }
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
    throw risas::cli::UsageError("--study is bins or tau, not '" + study + "'");
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
    const risas::cli::Args args(
        argc, argv,
        "risas_evaluate --data DATASET_ROOT [--out DIR] [--methods M,...] [--scenes S,...] [--sequences S,...]\n"
        "               [--pairs LABEL,...] [--study bins|tau] [--params P.yml] [--no-plots]\n"
        "Frame 1 against frame k of each sequence: NNDR matching, a match correct when its 3D points\n"
        "agree within 5 cm under the ground truth; PR curves, PR-AUC, and precision, recall and\n"
        "correct matches at ratio 0.8, per pair, sequence and scene type. Writes pairs.csv,\n"
        "curves.csv, summary.csv, summary.md, scale.csv and PNG plots into DIR.",
        {{"data", "DIR", "dataset root: <scene>/<sequence>/rgb_k.png ..., camera-intrinsics.txt"},
         {"out", "DIR", "output folder (default: evaluation)"},
         {"methods", "LIST", "methods to run (default: all of " + all_methods + ")"},
         {"scenes", "LIST", "scene types (default: texture,geometry)"},
         {"sequences", "LIST", "sequences (default: " + all_sequences + ")"},
         {"pairs", "LIST", "only these query labels, e.g. 3,5,square,rotate90"},
         {"study", "NAME", "parameter study instead of --methods: bins (n_pie x n_bin x n_vec) or tau"},
         {"no-plots", "", "do not run scripts/plot_evaluation.py"},
         risas::cli::paramsOption()});
    cv::setNumThreads(1);  // every method single-threaded, as the paper timed them
    const std::string root = args.get("data"), out = args.get("out", "evaluation");
    const risas::RisasParams params = risas::cli::paramsFrom(args);

    std::vector<std::unique_ptr<risas::eval::FeatureMethod>> methods;
    if (args.has("study")) {
      methods = studyMethods(args.get("study"), params);
    } else {
      for (const std::string& m : split(args.get("methods", all_methods))) methods.push_back(risas::eval::makeMethod(m, params));
    }
    std::vector<risas::eval::Pair> pairs =
        risas::eval::listPairs(root, split(args.get("scenes", "texture,geometry")), split(args.get("sequences", all_sequences)));
    if (args.has("pairs")) {
      const std::vector<std::string> wanted = split(args.get("pairs"));
      pairs.erase(std::remove_if(pairs.begin(), pairs.end(), [&](const risas::eval::Pair& p) {
                    return std::find(wanted.begin(), wanted.end(), p.label) == wanted.end();
                  }), pairs.end());
    }
    if (pairs.empty()) throw risas::InputError("no pairs to evaluate under " + root + " with these filters");

    risas::eval::Evaluator evaluator(std::move(methods), risas::findIntrinsics(root));
    std::vector<risas::eval::PairResult> results;
    for (size_t i = 0; i < pairs.size(); ++i) {
      const risas::eval::Pair& pair = pairs[i];
      std::cout << "[" << i + 1 << "/" << pairs.size() << "] " << pair.scene << "/" << pair.sequence << " "
                << pair.label << ":" << std::flush;
      for (risas::eval::PairResult& r : evaluator.evaluate(pair)) {
        std::cout << "  " << r.method << " " << std::fixed << std::setprecision(2) << r.auc;
        results.push_back(std::move(r));
      }
      std::cout << "\n";
    }
    risas::eval::writeReports(out, results, 0.8);
    std::cout << "\nPR-AUC (mean per sequence); details in " << out << "/summary.csv\n\n";
    std::ifstream summary(std::filesystem::path(out) / "summary.md");
    std::cout << summary.rdbuf();

    if (!args.has("no-plots")) {
      const std::string command = std::string(RISAS_PLOT_SCRIPT) + " " + out;
      if (std::system(command.c_str()) != 0) {
        std::cerr << "risas_evaluate: plotting failed (needs python3-matplotlib); run: " << command << "\n";
      }
    }
    return 0;
  });
}

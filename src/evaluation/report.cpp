#include "risas/evaluation/evaluator.hpp"

#include "risas/io.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

namespace risas::eval {
namespace {

struct Group {
  std::vector<const PairResult*> results;
  double sum(double (*f)(const PairResult&)) const {
    double total = 0.0;
    for (const PairResult* r : results) total += f(*r);
    return total;
  }
  double mean(double (*f)(const PairResult&)) const { return results.empty() ? 0.0 : sum(f) / results.size(); }
};

using Key = std::tuple<std::string, std::string, std::string>;  // scene, sequence, method

double success5(const PairResult& r) { return r.shares.recovered; }
double success2(const PairResult& r) { return r.shares.recovered_closely; }
double inliers(const PairResult& r) { return r.pose.inliers; }
double correct(const PairResult& r) { return r.at_ratio.correct; }
double distinctCorrect(const PairResult& r) { return r.distinct_correct; }
double repeatability(const PairResult& r) { return r.repeatability.rate(); }
double missed(const PairResult& r) { return r.shares.missed(); }
double missedPreferredByDepth(const PairResult& r) { return r.shares.missed_preferred_by_depth; }

// A sum of shares as text: a whole number as one (one seed), else to a tenth.
std::string sumText(double sum) {
  std::ostringstream out;
  const double tenths = std::round(sum * 10.0);
  out << std::fixed << std::setprecision(std::fmod(tenths, 10.0) == 0.0 ? 0 : 1) << tenths / 10.0;
  return out.str();
}

// Per scene: each method's pose success rates per sequence, and over all
// the scene's pairs, with mean inliers and correct matches over them.
void writePoseTable(std::ostream& md, const std::string& scene, const std::vector<std::string>& present,
                    const std::vector<std::string>& methods, const std::map<Key, Group>& groups, double report_ratio,
                    PoseRefit refit) {
  md << "### " << scene << ": pose recovered within 5 deg / 5 cm (2 deg / 2 cm)"
     << (refit == PoseRefit::Reprojection ? ", refitted on the reprojection errors" : "") << ", % of pairs\n\n| method |";
  for (const std::string& s : present) md << " " << s << " |";
  md << " all pairs | mean inliers | correct @" << std::setprecision(1) << report_ratio
     << " | distinct correct | keypoints | repeatability | misses the depth prefers |\n|---|";
  for (size_t i = 0; i < present.size() + 7; ++i) md << "---|";
  md << "\n";
  for (const std::string& m : methods) {
    Group all;
    md << "| " << m << " |";
    for (const std::string& s : present) {
      const auto g = groups.find({scene, s, m});
      if (g == groups.end()) {
        md << " – |";
        continue;
      }
      all.results.insert(all.results.end(), g->second.results.begin(), g->second.results.end());
      md << " " << std::setprecision(0) << 100.0 * g->second.mean(success5) << " (" << 100.0 * g->second.mean(success2)
         << ") |";
    }
    md << " " << std::setprecision(1) << 100.0 * all.mean(success5) << " (" << 100.0 * all.mean(success2) << ") | "
       << all.mean(inliers) << " | " << all.mean(correct) << " | " << all.mean(distinctCorrect) << " | "
       << std::setprecision(0)
       << all.mean([](const PairResult& r) { return 0.5 * (r.reference_keypoints + r.query_keypoints); }) << " | "
       << std::setprecision(2) << all.mean(repeatability) << " | " << sumText(all.sum(missedPreferredByDepth)) << " of "
       << sumText(all.sum(missed)) << " |\n";
  }
  md << "\n";
}

// A report's text, kept until it is complete and then written whole, so
// that a failed write is an error (writeTextFile) and not a short file.
std::ostringstream reportText() {
  std::ostringstream out;
  out << std::setprecision(6);
  return out;
}

void writeReport(const std::string& dir, const std::string& name, const std::ostringstream& text) {
  writeTextFile((std::filesystem::path(dir) / name).string(), text.str(), "report");
}

}  // namespace

void writeReports(const std::string& dir, const std::vector<PairResult>& results, double report_ratio,
                  PoseRefit refit) {
  std::filesystem::create_directories(dir);
  // Methods and sequences in the order they were run.
  std::vector<std::string> methods, scenes, sequences;
  const auto remember = [](std::vector<std::string>& list, const std::string& v) {
    if (std::find(list.begin(), list.end(), v) == list.end()) list.push_back(v);
  };
  std::map<Key, Group> groups;
  for (const PairResult& r : results) {
    remember(methods, r.method);
    remember(scenes, r.pair.scene);
    remember(sequences, r.pair.sequence);
    groups[{r.pair.scene, r.pair.sequence, r.method}].results.push_back(&r);
  }

  std::ostringstream pairs = reportText();
  pairs << "scene,sequence,pair,step,method,reference_keypoints,query_keypoints,dropped_reference,dropped_query,"
           "positives,pr_auc,precision,recall,correct,distinct_correct,matches,ms_per_frame,pose_estimated,inliers,"
           "rotation_error_deg,alignment_error_m,success_5deg_5cm,success_2deg_2cm,repeatable,visible,inlier_spread_m,"
           "depth_agreement,depth_agreement_truth\n";
  for (const PairResult& r : results) {
    pairs << r.pair.scene << "," << r.pair.sequence << "," << r.pair.label << "," << r.pair.step << "," << r.method
          << "," << r.reference_keypoints << "," << r.query_keypoints << "," << r.dropped_reference << ","
          << r.dropped_query << "," << r.positives << "," << r.auc << "," << r.at_ratio.precision << ","
          << r.at_ratio.recall << "," << r.at_ratio.correct << "," << r.distinct_correct << "," << r.at_ratio.matches
          << "," << r.ms_per_frame << "," << r.pose.estimated << "," << r.pose.inliers << ","
          << r.pose.error.rotation_deg << "," << r.pose.error.alignment_m << "," << success5(r) << "," << success2(r) << ","
          << r.repeatability.repeated << "," << r.repeatability.visible << "," << r.pose.inlier_spread_m << ","
          << r.depth_agreement << "," << r.depth_agreement_truth << "\n";
  }
  writeReport(dir, "pairs.csv", pairs);

  std::ostringstream curves = reportText();
  curves << "scene,sequence,method,ratio,precision,recall\n";
  std::ostringstream summary = reportText();
  summary << "scene,sequence,method,pairs,mean_pr_auc,precision,recall,correct,distinct_correct,keypoints,"
             "ms_per_frame,success_5deg_5cm,success_2deg_2cm,mean_inliers,repeatability,misses,misses_preferred_by_depth\n";
  for (const auto& [key, group] : groups) {
    const auto& [scene, sequence, method] = key;
    std::vector<Candidate> pooled;
    int positives = 0;
    for (const PairResult* r : group.results) {
      pooled.insert(pooled.end(), r->candidates.begin(), r->candidates.end());
      positives += r->positives;
    }
    const std::vector<PrPoint> curve = prCurve(pooled, positives);
    for (int step = 1; step <= 100; ++step) {
      const PrPoint p = atThreshold(curve, step / 100.0);
      if (p.matches > 0) curves << scene << "," << sequence << "," << method << "," << p.ratio << "," << p.precision << "," << p.recall << "\n";
    }
    summary << scene << "," << sequence << "," << method << "," << group.results.size() << ","
            << group.mean([](const PairResult& r) { return r.auc; }) << ","
            << group.mean([](const PairResult& r) { return r.at_ratio.precision; }) << ","
            << group.mean([](const PairResult& r) { return r.at_ratio.recall; }) << ","
            << group.mean(correct) << "," << group.mean(distinctCorrect) << ","
            << group.mean([](const PairResult& r) { return 0.5 * (r.reference_keypoints + r.query_keypoints); }) << ","
            << group.mean([](const PairResult& r) { return r.ms_per_frame; }) << "," << group.mean(success5) << ","
            << group.mean(success2) << "," << group.mean(inliers) << "," << group.mean(repeatability) << ","
            << sumText(group.sum(missed)) << "," << sumText(group.sum(missedPreferredByDepth)) << "\n";
  }
  writeReport(dir, "curves.csv", curves);
  writeReport(dir, "summary.csv", summary);

  std::ostringstream scale = reportText();
  scale << "scene,method,step,correct_percentage,correct,matches\n";
  for (const PairResult& r : results) {
    if (r.pair.sequence != "scale") continue;
    const double percent = r.at_ratio.matches ? 100.0 * r.at_ratio.correct / r.at_ratio.matches : 0.0;
    scale << r.pair.scene << "," << r.method << "," << r.pair.step << "," << percent << "," << r.at_ratio.correct
          << "," << r.at_ratio.matches << "\n";
  }
  writeReport(dir, "scale.csv", scale);

  std::ostringstream md = reportText();
  md << std::fixed;
  for (const std::string& scene : scenes) {
    md << "### " << scene << ": mean PR-AUC\n\n| method |";
    std::vector<std::string> present;
    for (const std::string& s : sequences) {
      if (std::any_of(groups.begin(), groups.end(), [&](const auto& g) {
            return std::get<0>(g.first) == scene && std::get<1>(g.first) == s;
          })) {
        present.push_back(s);
      }
    }
    for (const std::string& s : present) md << " " << s << " |";
    md << " mean | correct @" << std::setprecision(1) << report_ratio << " | ms/frame |\n|---|";
    for (size_t i = 0; i < present.size() + 3; ++i) md << "---|";
    md << "\n";
    std::map<std::string, double> best;
    for (const std::string& s : present) {
      for (const std::string& m : methods) {
        const auto g = groups.find({scene, s, m});
        if (g != groups.end()) best[s] = std::max(best[s], g->second.mean([](const PairResult& r) { return r.auc; }));
      }
    }
    for (const std::string& m : methods) {
      md << "| " << m << " |";
      double auc_sum = 0.0, correct_sum = 0.0, ms_sum = 0.0;
      int n = 0;
      for (const std::string& s : present) {
        const auto g = groups.find({scene, s, m});
        if (g == groups.end()) {
          md << " – |";
          continue;
        }
        const double auc = g->second.mean([](const PairResult& r) { return r.auc; });
        const bool is_best = auc >= best[s] - 1e-12;
        md << " " << (is_best ? "**" : "") << std::setprecision(3) << auc << (is_best ? "**" : "") << " |";
        auc_sum += auc;
        correct_sum += g->second.mean(correct);
        ms_sum += g->second.mean([](const PairResult& r) { return r.ms_per_frame; });
        ++n;
      }
      if (n == 0) n = 1;
      md << " " << std::setprecision(3) << auc_sum / n << " | " << std::setprecision(1) << correct_sum / n << " | "
         << std::setprecision(1) << ms_sum / n << " |\n";
    }
    md << "\n";
    writePoseTable(md, scene, present, methods, groups, report_ratio, refit);
  }
  writeReport(dir, "summary.md", md);
}

}  // namespace risas::eval

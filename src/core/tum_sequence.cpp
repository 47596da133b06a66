#include "risas/tum_sequence.hpp"

#include "risas/errors.hpp"
#include "risas/io.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace risas {
namespace fs = std::filesystem;
namespace {

struct Line {
  int number;
  std::vector<std::string> fields;
};

// The file's non-comment, non-blank lines split at white space.
std::vector<Line> readLines(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open " + path.string());
  std::vector<Line> lines;
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    const size_t first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;
    std::istringstream words(text);
    Line line{number, {}};
    for (std::string w; words >> w;) line.fields.push_back(w);
    lines.push_back(std::move(line));
  }
  return lines;
}

double number(const fs::path& path, const Line& line, size_t field) {
  const std::string& text = line.fields[field];
  size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value)) {
    throw InputError(path.string() + " line " + std::to_string(line.number) + ": '" + text + "' is not a finite number");
  }
  return value;
}

struct Listed {
  std::vector<double> stamps;
  std::vector<std::string> paths;
};

Listed readList(const fs::path& dir, const char* name) {
  const fs::path path = dir / name;
  if (!fs::exists(path)) throw InputError("no " + std::string(name) + " in " + dir.string() + " (a TUM RGB-D folder)");
  Listed listed;
  for (const Line& line : readLines(path)) {
    if (line.fields.size() != 2) {
      throw InputError(path.string() + " line " + std::to_string(line.number) + ": expected 'timestamp filename'");
    }
    const fs::path image = dir / line.fields[1];
    if (!fs::is_regular_file(image)) {
      throw InputError(path.string() + " line " + std::to_string(line.number) + ": no file " + image.string());
    }
    listed.stamps.push_back(number(path, line, 0));
    listed.paths.push_back(image.string());
  }
  return listed;
}

}  // namespace

std::vector<StampedPose> readTumTrajectory(const std::string& path_name) {
  const fs::path path(path_name);
  std::vector<StampedPose> poses;
  for (const Line& line : readLines(path)) {
    if (line.fields.size() != 8) {
      throw InputError(path.string() + " line " + std::to_string(line.number) + ": expected 'timestamp tx ty tz qx qy qz qw'");
    }
    double v[8];
    for (size_t f = 0; f < 8; ++f) v[f] = number(path, line, f);
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (!(q.norm() > 1e-6)) throw InputError(path.string() + " line " + std::to_string(line.number) + ": the quaternion is zero");
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    poses.push_back({v[0], T});
  }
  return poses;
}

void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  std::ostringstream out;
  out << "# timestamp tx ty tz qx qy qz qw\n" << std::fixed;
  for (const StampedPose& p : poses) {
    const Eigen::Quaterniond q(p.world_T_camera.linear());
    const Eigen::Vector3d t = p.world_T_camera.translation();
    out << std::setprecision(6) << p.stamp << std::setprecision(7) << " " << t.x() << " " << t.y() << " " << t.z()
        << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w() << "\n";
  }
  writeTextFile(path, out.str(), "trajectory");
}

std::vector<std::pair<size_t, size_t>> associateStamps(const std::vector<double>& a, const std::vector<double>& b,
                                                       double max_difference) {
  struct Candidate {
    double difference;
    size_t i, j;
  };
  std::vector<Candidate> candidates;
  // b sorted by stamp: each a looks only at the b within the tolerance.
  std::vector<size_t> order(b.size());
  for (size_t j = 0; j < b.size(); ++j) order[j] = j;
  std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return b[x] < b[y]; });
  for (size_t i = 0; i < a.size(); ++i) {
    auto it = std::lower_bound(order.begin(), order.end(), a[i] - max_difference,
                               [&](size_t j, double v) { return b[j] < v; });
    for (; it != order.end() && b[*it] < a[i] + max_difference; ++it) {
      const double d = std::abs(a[i] - b[*it]);
      if (d < max_difference) candidates.push_back({d, i, *it});
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.difference < y.difference; });
  std::vector<char> used_a(a.size(), 0), used_b(b.size(), 0);
  std::vector<std::pair<size_t, size_t>> matches;
  for (const Candidate& c : candidates) {
    if (used_a[c.i] || used_b[c.j]) continue;
    used_a[c.i] = used_b[c.j] = 1;
    matches.emplace_back(c.i, c.j);
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

TumSequence readTumSequence(const std::string& dir_name, double max_difference, double truth_offset) {
  const fs::path dir(dir_name);
  if (!fs::is_directory(dir)) throw InputError("no folder " + dir_name);
  // A NaN among the stamps would break the sort's ordering below.
  if (!std::isfinite(truth_offset)) {
    throw InputError("the ground truth's offset for " + dir_name + " is not a finite number of seconds");
  }
  const Listed rgb = readList(dir, "rgb.txt"), depth = readList(dir, "depth.txt");

  TumSequence sequence;
  const fs::path gt = dir / "groundtruth.txt";
  if (fs::exists(gt)) sequence.ground_truth = readTumTrajectory(gt.string());
  for (StampedPose& p : sequence.ground_truth) p.stamp += truth_offset;
  const std::vector<StampedPose>& truth = sequence.ground_truth;
  std::vector<size_t> by_stamp(truth.size());
  for (size_t k = 0; k < by_stamp.size(); ++k) by_stamp[k] = k;
  std::sort(by_stamp.begin(), by_stamp.end(), [&](size_t x, size_t y) { return truth[x].stamp < truth[y].stamp; });

  sequence.has_ground_truth = !truth.empty();
  sequence.max_difference = max_difference;
  const auto pairs = associateStamps(rgb.stamps, depth.stamps, max_difference);
  sequence.unmatched_rgb = static_cast<int>(rgb.stamps.size() - pairs.size());
  sequence.unmatched_depth = static_cast<int>(depth.stamps.size() - pairs.size());
  for (const auto& [i, j] : pairs) {
    TumFrame f;
    f.stamp = rgb.stamps[i];
    f.rgb = rgb.paths[i];
    f.depth = depth.paths[j];
    f.depth_stamp = depth.stamps[j];
    // The nearest ground-truth stamp, on either side.
    auto it = std::lower_bound(by_stamp.begin(), by_stamp.end(), f.stamp,
                               [&](size_t k, double v) { return truth[k].stamp < v; });
    double best = max_difference;
    for (auto c : {it, it == by_stamp.begin() ? it : it - 1}) {
      if (c == by_stamp.end()) continue;
      const double d = std::abs(truth[*c].stamp - f.stamp);
      if (d < best) best = d, f.world_T_camera = truth[*c].world_T_camera;
    }
    sequence.without_pose += !f.world_T_camera;
    sequence.frames.push_back(std::move(f));
  }
  std::sort(sequence.frames.begin(), sequence.frames.end(),
            [](const TumFrame& x, const TumFrame& y) { return x.stamp < y.stamp; });
  if (sequence.frames.empty()) {
    throw InputError("no colour image in " + dir_name + " has a depth image within " + std::to_string(max_difference) +
                     " s of it");
  }
  return sequence;
}

std::string leftOutOf(const TumSequence& sequence) {
  const size_t frames = sequence.frames.size();
  std::ostringstream text;
  text << sequence.max_difference;
  const std::string within = " within " + text.str() + " s";
  std::vector<std::string> parts;
  if (sequence.unmatched_rgb > 0) {
    parts.push_back(std::to_string(sequence.unmatched_rgb) + " of " + std::to_string(frames + sequence.unmatched_rgb) +
                    " colour images have no depth image" + within);
  }
  if (sequence.unmatched_depth > 0) {
    parts.push_back(std::to_string(sequence.unmatched_depth) + " of " +
                    std::to_string(frames + sequence.unmatched_depth) + " depth images have no colour image" + within);
  }
  if (sequence.has_ground_truth && sequence.without_pose > 0) {
    parts.push_back(std::to_string(sequence.without_pose) + " of " + std::to_string(frames) +
                    " frames have no ground-truth pose" + within);
  }
  std::string sentence;
  for (const std::string& part : parts) sentence += (sentence.empty() ? "" : "; ") + part;
  return sentence;
}

TumImages readTumImages(const TumFrame& frame) {
  const RgbdImages images = readRgbdImages(frame.rgb, frame.depth);
  return {images.bgr, depthFromUnits(images.depth_mm, kTumDepthUnitsPerMetre)};
}

RgbdFrame loadTumFrame(const TumFrame& frame, const Intrinsics& intrinsics) {
  return loadRgbdFrame(frame.rgb, frame.depth, intrinsics, kTumDepthUnitsPerMetre);
}

}  // namespace risas

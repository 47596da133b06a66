#include "risas/evaluation/protocol.hpp"

#include "risas/errors.hpp"
#include "risas/io.hpp"
#include "risas/tum_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>

namespace risas::eval {
namespace fs = std::filesystem;

namespace {

// p1 = R pk + t of frame k, from corrected/ if asked for and the sequence has it.
Eigen::Isometry3d readPose(const fs::path& dir, int k, GroundTruthPoses which) {
  const bool corrected = which == GroundTruthPoses::Corrected && fs::exists(dir / "corrected");
  const fs::path poses = corrected ? dir / "corrected" : dir;
  return readPoseFiles((poses / ("R1-" + std::to_string(k) + ".txt")).string(),
                       (poses / ("T1-" + std::to_string(k) + ".txt")).string());
}

// Named under the root by listPairs.
FramePaths frame(const fs::path& dir, const std::string& rgb_name, const std::string& depth_name) {
  FramePaths f;
  f.rgb = (dir / rgb_name).string();
  f.depth = (dir / depth_name).string();
  return f;
}

bool exists(const FramePaths& f) { return fs::exists(f.rgb) && fs::exists(f.depth); }

}  // namespace

const std::vector<std::string>& evaluatedSequences() {
  static const std::vector<std::string> sequences = {"viewchange", "illum", "scale", "rotate", "synthetic_rotate"};
  return sequences;
}

std::vector<Pair> listPairs(const std::string& root, const std::vector<std::string>& scenes,
                            const std::vector<std::string>& sequences, GroundTruthPoses poses) {
  std::vector<Pair> pairs;
  for (const std::string& scene : scenes) {
    for (const std::string& sequence : sequences) {
      const fs::path dir = fs::path(root) / scene / sequence;
      if (!fs::is_directory(dir)) continue;
      const auto add = [&](Pair p) {
        p.scene = scene;
        p.sequence = sequence;
        for (FramePaths* f : {&p.reference, &p.query}) {
          f->name = scene + "/" + sequence + "/" + fs::path(f->rgb).filename().string();
        }
        if (exists(p.reference) && exists(p.query)) pairs.push_back(std::move(p));
      };
      if (sequence == "illum") {
        // The paper's four intensity transforms of frame 1, then natural light changes.
        const char* transforms[] = {"square", "squareRoot", "cube", "cubeRoot"};
        for (int i = 0; i < 4; ++i) {
          Pair p;
          p.label = transforms[i];
          p.step = i + 1;
          p.reference = frame(dir, "rgb_1.png", "depth_1.png");
          p.query = frame(dir, std::string("rgb_1_") + transforms[i] + ".png", "depth_1.png");
          add(p);
        }
        for (int k = 2; fs::exists(dir / ("rgb_" + std::to_string(k) + ".png")); ++k) {
          Pair p;
          p.label = std::to_string(k);
          p.step = 4 + k;
          p.reference = frame(dir, "rgb_1.png", "depth_1.png");
          p.query = frame(dir, "rgb_" + std::to_string(k) + ".png", "depth_" + std::to_string(k) + ".png");
          add(p);
        }
      } else if (sequence == "synthetic_rotate") {
        std::vector<std::pair<int, int>> found;  // (frame N, angle)
        const std::regex name("rgb_([0-9]+)_rotate([0-9]+)\\.png");
        for (const auto& entry : fs::directory_iterator(dir)) {
          std::smatch m;
          const std::string file = entry.path().filename().string();
          if (std::regex_match(file, m, name)) found.emplace_back(std::stoi(m[1]), std::stoi(m[2]));
        }
        std::sort(found.begin(), found.end());
        for (const auto& [n, angle] : found) {
          Pair p;
          p.label = "rotate" + std::to_string(angle);
          p.step = angle;
          p.reference = frame(dir, "rgb_" + std::to_string(n) + ".png", "depth_" + std::to_string(n) + ".png");
          const std::string suffix = std::to_string(n) + "_rotate" + std::to_string(angle) + ".png";
          p.query = frame(dir, "rgb_" + suffix, "depth_" + suffix);
          p.image_rotation_deg = angle;
          add(p);
        }
      } else {
        for (int k = 2; fs::exists(dir / ("rgb_" + std::to_string(k) + ".png")); ++k) {
          Pair p;
          p.label = std::to_string(k);
          p.step = k;
          p.reference = frame(dir, "rgb_1.png", "depth_1.png");
          p.query = frame(dir, "rgb_" + std::to_string(k) + ".png", "depth_" + std::to_string(k) + ".png");
          p.ref_T_query = readPose(dir, k, poses);
          add(p);
        }
      }
    }
  }
  return pairs;
}

cv::Point3f keypointPoint(const cv::Mat& depth_metres, const Intrinsics& K, const cv::Point2f& pixel) {
  const int u = cvRound(pixel.x), v = cvRound(pixel.y);
  float z[9];
  int n = 0;
  for (int dv = -1; dv <= 1; ++dv) {
    for (int du = -1; du <= 1; ++du) {
      const int r = v + dv, c = u + du;
      if (r < 0 || c < 0 || r >= depth_metres.rows || c >= depth_metres.cols) continue;
      const float d = depth_metres.at<float>(r, c);
      if (!std::isnan(d)) z[n++] = d;
    }
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  if (n == 0) return {nan, nan, nan};
  std::nth_element(z, z + n / 2, z + n);
  return K.backProject(pixel.x, pixel.y, z[n / 2]);
}

cv::Point2f unrotatePixel(const cv::Point2f& pixel, double rotation_deg, const cv::Point2f& centre) {
  // On screen counter-clockwise by A, with v pointing down: q - c = M(A) (p - c),
  // M(A) = [cos A, sin A; -sin A, cos A]; so p - c = M(A)^T (q - c).
  const double a = rotation_deg * CV_PI / 180.0, c = std::cos(a), s = std::sin(a);
  const double dx = pixel.x - centre.x, dy = pixel.y - centre.y;
  return {static_cast<float>(centre.x + c * dx - s * dy), static_cast<float>(centre.y + s * dx + c * dy)};
}

std::vector<Pair> listTumPairs(const std::string& dir, const TumSequence& sequence, const std::vector<int>& gaps,
                               int stride) {
  if (stride < 1) throw InputError("the pair stride must be positive, not " + std::to_string(stride));
  const std::string scene = fs::path(dir).lexically_normal().filename().empty()
                                ? fs::path(dir).lexically_normal().parent_path().filename().string()
                                : fs::path(dir).lexically_normal().filename().string();
  std::vector<Pair> pairs;
  const auto& frames = sequence.frames;
  for (int gap : gaps) {
    if (gap < 1) throw InputError("a frame gap must be positive, not " + std::to_string(gap));
    for (size_t i = 0; i + static_cast<size_t>(gap) < frames.size(); i += static_cast<size_t>(stride)) {
      const TumFrame &a = frames[i], &b = frames[i + static_cast<size_t>(gap)];
      if (!a.world_T_camera || !b.world_T_camera) continue;
      Pair p;
      p.scene = scene;
      p.sequence = "gap" + std::to_string(gap);
      p.label = std::to_string(i) + "+" + std::to_string(gap);
      p.step = gap;
      p.reference = {a.rgb, a.depth, kTumDepthUnitsPerMetre, fs::path(a.rgb).lexically_relative(dir).generic_string()};
      p.query = {b.rgb, b.depth, kTumDepthUnitsPerMetre, fs::path(b.rgb).lexically_relative(dir).generic_string()};
      p.ref_T_query = a.world_T_camera->inverse() * *b.world_T_camera;
      pairs.push_back(std::move(p));
    }
  }
  return pairs;
}

}  // namespace risas::eval

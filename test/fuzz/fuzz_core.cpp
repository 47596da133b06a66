// Fuzz driver for the core's entry points: RgbdFrame, Risas::extract /
// detect / compute, matchDescriptors, estimateRigidMotion and RisasParams
// read from text, a twist from a motion found, a TUM RGB-D folder's lists
// and trajectory (readTumSequence, readTumTrajectory), a features file
// (readFeatures) and image files (readRgbdImages). One input drives one
// case of each.
//
// Invariants it holds the core to (a breach aborts, and so does any
// sanitizer report):
//   - the only exception is risas::InputError (for text that is no
//     FileStorage at all, OpenCV's cv::Exception from its parser, which
//     RisasParams::load turns into std::runtime_error);
//   - keypoints lie inside the image; descriptors have one row per keypoint,
//     descriptorSize() columns, finite values and unit length; geometry has
//     one entry per keypoint with a finite point in front of the camera and
//     a unit normal;
//   - matches index existing rows; a motion's inlier mask has one entry per
//     match and counts num_inliers, its transform is finite;
//   - a TUM folder read gives frames in ascending colour stamps, each of an
//     existing colour and depth file and a depth stamp within the
//     tolerance, and poses that are finite rotations and translations;
//   - a features file read has one CV_32F descriptor row per keypoint and
//     geometry for none or for each;
//   - an image file is read whole or refused, a JPEG cut short refused.
//
// Built two ways (test/fuzz/CMakeLists.txt): with clang and -fsanitize=fuzzer
// as a libFuzzer target, and everywhere as `risas_fuzz_loop`, a seeded,
// time-bounded loop over random inputs (fuzz_loop_main.cpp).
#include "fuzz_support.hpp"
#include "risas/errors.hpp"
#include "risas/io.hpp"
#include "risas/matcher.hpp"
#include "risas/motion.hpp"
#include "risas/odometry.hpp"
#include "risas/params.hpp"
#include "risas/risas.hpp"
#include "risas/tum_sequence.hpp"
#include "risas/twist.hpp"

#include <opencv2/imgcodecs.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace risas_fuzz;

void fuzzFrame(Bytes& in) {
  static const int colour_types[] = {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1, CV_8UC2};
  static const int depth_types[] = {CV_16UC1, CV_32FC1, CV_8UC1, CV_16UC3};
  // Most cases a frame the core accepts, so that the stages behind the
  // validation are reached; the rest anything at all.
  const bool plausible = in.byte() % 8 != 0;
  cv::Size size;
  size.width = in.in(0, 72), size.height = in.in(0, 56);
  cv::Size depth_size = size;
  int colour_type = colour_types[in.byte() % 5], depth_type = depth_types[in.byte() % 4];
  // One value per statement throughout: a call's arguments are evaluated in
  // the compiler's order, and an input must mean the same to every build.
  risas::Intrinsics K;
  K.fx = in.number(1.0, 200.0), K.fy = in.number(1.0, 200.0), K.cx = in.number(-5.0, 80.0), K.cy = in.number(-5.0, 60.0);
  if (plausible) {
    size.width = in.in(2, 72), size.height = in.in(2, 56), depth_size = size;
    colour_type = colour_types[in.byte() % 3], depth_type = depth_types[in.byte() % 2];
    K.fx = in.in(20, 150), K.fy = in.in(20, 150), K.cx = in.in(0, size.width), K.cy = in.in(0, size.height);
  } else if (in.byte() % 8 == 0) {
    depth_size.width = in.in(0, 72), depth_size.height = in.in(0, 56);
  }
  const cv::Mat colour = image(in, size, colour_type);
  const cv::Mat depth = image(in, depth_size, depth_type);
  risas::RgbdFrame frame;
  try {
    frame = risas::RgbdFrame(colour, depth, K, in.byte() % 2 ? risas::ColorOrder::RGB : risas::ColorOrder::BGR);
  } catch (const risas::InputError&) {
    return;
  }
  cv::Ptr<risas::Risas> risas;
  try {
    risas = risas::Risas::create(params(in));
  } catch (const risas::InputError&) {
    return;
  }
  cv::Mat mask;
  if (in.byte() % 4 == 0) mask = image(in, frame.size(), CV_8UC1);
  const risas::Features f = risas->extract(frame, mask);
  checkFeatures(frame, f.keypoints, f.descriptors, f.geometry, risas->descriptorSize());

  // Given keypoints anywhere, also off the image and not finite.
  std::vector<cv::KeyPoint> keypoints;
  for (int i = in.in(0, 12); i > 0; --i) {
    cv::KeyPoint k;
    k.pt.x = static_cast<float>(in.number(-10.0, 80.0));
    k.pt.y = static_cast<float>(in.number(-10.0, 60.0));
    k.size = static_cast<float>(in.number(0.0, 40.0));
    keypoints.push_back(k);
  }
  cv::Mat descriptors;
  std::vector<risas::KeypointGeometry> geometry;
  risas->compute(frame, keypoints, descriptors, &geometry);
  checkFeatures(frame, keypoints, descriptors, geometry, risas->descriptorSize());
}

// The odometry's refit of a RANSAC estimate keeps its inliers, keeps a
// valid motion finite, and refuses nothing but a Huber width that is not
// positive and finite (the estimate's indices were checked by RANSAC).
void refineAndCheck(Bytes& in, const std::vector<cv::Point3f>& q, const std::vector<cv::Point3f>& t,
                    const std::vector<cv::DMatch>& matches, const risas::MotionEstimate& m) {
  const double huber = in.number(0.0, 0.05);
  const bool usable = huber > 0.0 && std::isfinite(huber);
  try {
    const risas::MotionEstimate r = risas::refineByReprojection(q, t, matches, m, huber);
    require(usable, "a Huber width that is not positive and finite refused");
    require(r.valid == m.valid && r.inliers == m.inliers && r.num_inliers == m.num_inliers, "inliers kept");
    require(!r.valid || r.train_T_query.matrix().allFinite(), "finite refined motion");
  } catch (const risas::InputError&) {
    require(!usable, "only the Huber width refused");
  }
}

// A twist from a valid motion and its covariance (from the inliers, as the
// odometry makes it) refuses nothing but a time that is no interval, and is
// finite otherwise.
void twistAndCheck(Bytes& in, const risas::MotionEstimate& m, const std::vector<cv::Point3f>& q,
                   const std::vector<cv::DMatch>& matches) {
  std::vector<Eigen::Vector3d> rotated;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (!m.inliers[i]) continue;
    const cv::Point3f& p = q[static_cast<size_t>(matches[i].queryIdx)];
    rotated.push_back(m.train_T_query.linear() * Eigen::Vector3d(p.x, p.y, p.z));
  }
  const Eigen::Matrix<double, 6, 6> covariance = risas::motionCovariance(rotated, m.rmse);
  const double dt = in.number(0.0, 0.2);
  const bool usable = dt >= risas::kShortestTwistInterval && std::isfinite(dt);
  try {
    const risas::Twist twist = risas::twistFromMotion(m.train_T_query, covariance, dt);
    require(usable, "a time that is no interval refused");
    require(twist.velocity.allFinite() && twist.covariance.allFinite(), "finite twist");
    // A camera within a metre of the base, turned any way.
    const Eigen::Isometry3d base_T_camera = Eigen::Translation3d(in.in(-100, 100) * 0.01, 0.0, 0.3) *
                                            Eigen::AngleAxisd(in.in(-314, 314) * 0.01, Eigen::Vector3d::UnitZ());
    const risas::Twist base = risas::transformTwist(twist, base_T_camera);
    require(base.velocity.allFinite() && base.covariance.allFinite(), "finite twist on the base");
  } catch (const risas::InputError&) {
    require(!usable, "only the time refused");
  }
}

void fuzzMatchingAndMotion(Bytes& in) {
  const int rows_q = in.in(0, 20);
  const int rows_t = in.in(0, 20);
  const int cols = in.in(1, 8);
  const int cols_t = in.byte() % 8 ? cols : in.in(1, 8);
  cv::Mat query(rows_q, cols, CV_32F), train(rows_t, cols_t, CV_32F);
  for (cv::Mat* m : {&query, &train}) {
    for (int i = 0; i < m->rows * m->cols; ++i) m->at<float>(i / m->cols, i % m->cols) = static_cast<float>(in.number(-1, 1));
  }
  std::vector<cv::DMatch> matches;
  risas::MatchParams match;
  match.cross_check = in.byte() % 2;
  try {
    matches = risas::matchDescriptors(query, train, match);
    for (const cv::DMatch& m : matches) {
      require(m.queryIdx >= 0 && m.queryIdx < rows_q && m.trainIdx >= 0 && m.trainIdx < rows_t, "match indices");
    }
  } catch (const risas::InputError&) {
  }
  std::vector<cv::Point3f> q, t;
  const auto point = [&in] {
    cv::Point3f p;
    p.x = static_cast<float>(in.number(-2, 2)), p.y = static_cast<float>(in.number(-2, 2));
    p.z = static_cast<float>(in.number(0, 4));
    return p;
  };
  // Most train points are the query points moved by one rigid motion (and
  // now and then nudged), and most matches pair them, so that RANSAC finds
  // a valid estimate for the refit to work on; the rest are arbitrary (and
  // one match in 32 may index a point that does not exist).
  const Eigen::Isometry3d motion_truth = Eigen::Translation3d(in.number(-0.5, 0.5), 0.1, 0.2) *
                                         Eigen::AngleAxisd(in.in(-30, 30) * 0.01, Eigen::Vector3d(0.6, 0.8, 0.0));
  for (int i = in.in(0, 30); i > 0; --i) {
    q.push_back(point());
    if (in.byte() % 4) {
      const Eigen::Vector3d moved = motion_truth * Eigen::Vector3d(q.back().x, q.back().y, q.back().z);
      const double nudge = in.byte() % 4 ? 0.0 : in.number(-0.05, 0.05);
      t.emplace_back(static_cast<float>(moved.x() + nudge), static_cast<float>(moved.y()),
                     static_cast<float>(moved.z()));
    } else {
      t.push_back(point());
    }
  }
  matches.clear();
  for (int i = in.in(0, 40); i > 0; --i) {
    cv::DMatch m;
    if (in.byte() % 32) {
      m.queryIdx = m.trainIdx = static_cast<int>(matches.size()) % std::max<int>(1, static_cast<int>(q.size()));
    } else {
      m.queryIdx = in.in(-1, 31), m.trainIdx = in.in(-1, 31);
    }
    matches.push_back(m);
  }
  risas::MotionParams motion;
  motion.confidence = in.byte() % 4 ? 0.999 : 1.0;
  motion.max_iterations = in.in(1, 300);
  try {
    const risas::MotionEstimate m = risas::estimateRigidMotion(q, t, matches, motion);
    require(m.inliers.size() == matches.size(), "one inlier flag per match");
    int count = 0;
    for (char c : m.inliers) count += c != 0;
    require(!m.valid || count == m.num_inliers, "inliers counted");
    require(!m.valid || m.train_T_query.matrix().allFinite(), "finite motion");
    refineAndCheck(in, q, t, matches, m);
    if (m.valid) twistAndCheck(in, m, q, matches);
  } catch (const risas::InputError&) {
  }
}

// A folder of the process's own for the file cases, made once and removed at
// exit, with one colour and one depth image (empty: the TUM reader only
// checks that they exist).
class FuzzFolder {
 public:
  FuzzFolder() : path_(std::filesystem::temp_directory_path() / ("risas_fuzz_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_ / "rgb");
    std::filesystem::create_directories(path_ / "depth");
    std::ofstream(path_ / "rgb" / "a.png") << "x";
    std::ofstream(path_ / "depth" / "a.png") << "x";
  }
  ~FuzzFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

bool isRigid(const Eigen::Isometry3d& T) {
  const Eigen::Matrix3d R = T.linear();
  return T.matrix().allFinite() && (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-9 &&
         R.determinant() > 0.0;
}

// A number as a line may hold it. Mostly `ordinary`; now and then one the
// reader must refuse (nan, inf, beyond a double's range, a letter after it)
// or any double (Bytes::number). The loop's bytes are often small and 0
// once the input runs out, so those give the ordinary value.
std::string numberText(Bytes& in, double ordinary) {
  char text[40];
  switch (in.byte() % 64) {
    case 59: std::snprintf(text, sizeof text, "%.17g", in.number(-1e9, 1e9)); return text;
    case 60: return "nan";
    case 61: return "-inf";
    case 62: return "1e999";
    case 63: return "1.5x";
    default: std::snprintf(text, sizeof text, "%.9g", ordinary); return text;
  }
}

// Lines of rgb.txt or depth.txt ("stamp file", the one image of the folder
// or a missing one) or of groundtruth.txt (eight numbers), now and then a
// comment, a blank line, a field too few or too many, or raw bytes.
std::string tumLines(Bytes& in, const std::string& image) {
  std::string text;
  for (int n = in.in(0, 10); n > 0; --n) {
    const int kind = in.byte() % 32;  // 0 .. 26: a line as it should be
    std::string line;
    if (kind == 27) {
      line = "# comment";
    } else if (kind == 29) {
      for (int k = in.in(0, 12); k > 0; --k) line += static_cast<char>(in.byte());
    } else if (kind != 28) {
      line = numberText(in, 10.0 + 0.005 * in.in(0, 40));  // a 5 ms grid: colour, depth and poses pair
      if (!image.empty()) {
        line += kind == 30 ? " missing.png" : " " + image;
      } else {
        for (int k = kind == 30 ? 6 : 7; k > 0; --k) line += " " + numberText(in, (in.byte() - 100) / 100.0);
      }
      if (kind == 31) line += " extra";
    }
    text += line + "\n";
  }
  return text;
}

void fuzzTumFolder(Bytes& in) {
  static const FuzzFolder folder;
  const std::filesystem::path& dir = folder.path();
  std::ofstream(dir / "rgb.txt") << tumLines(in, "rgb/a.png");
  std::ofstream(dir / "depth.txt") << tumLines(in, "depth/a.png");
  const std::filesystem::path gt = dir / "groundtruth.txt";
  if (in.byte() % 4) {
    std::ofstream(gt) << tumLines(in, "");
  } else {
    std::filesystem::remove(gt);
  }
  const double tolerance = in.byte() % 8 ? 0.02 : in.number(0, 0.2);
  const double truth_offset = in.byte() % 4 ? 0.0 : in.number(-0.1, 0.1);  // up to 20 of the 5 ms steps, or not finite
  try {
    const risas::TumSequence s = risas::readTumSequence(dir.string(), tolerance, truth_offset);
    require(!s.frames.empty() && s.unmatched_rgb >= 0 && s.unmatched_depth >= 0, "frames and counts");
    for (size_t i = 0; i < s.frames.size(); ++i) {
      const risas::TumFrame& f = s.frames[i];
      require(i == 0 || s.frames[i - 1].stamp <= f.stamp, "colour stamps ascending");
      require(std::isfinite(f.stamp) && std::abs(f.stamp - f.depth_stamp) < tolerance, "depth within the tolerance");
      require(std::filesystem::is_regular_file(f.rgb) && std::filesystem::is_regular_file(f.depth), "files exist");
      require(!f.world_T_camera || isRigid(*f.world_T_camera), "a frame's pose is a rigid motion");
      // It is one of the ground truth's poses kept for scoring, stamped
      // (the offset added) within the tolerance of the frame.
      require(!f.world_T_camera || std::any_of(s.ground_truth.begin(), s.ground_truth.end(),
                                               [&](const risas::StampedPose& p) {
                                                 return std::abs(p.stamp - f.stamp) < tolerance &&
                                                        p.world_T_camera.matrix() == f.world_T_camera->matrix();
                                               }),
              "a frame's pose is a ground-truth pose near its stamp");
    }
    require(s.has_ground_truth == !s.ground_truth.empty(), "the ground truth is there exactly when it has a pose");
    const bool all_paired =
        s.unmatched_rgb == 0 && s.unmatched_depth == 0 && (!s.has_ground_truth || s.without_pose == 0);
    require(risas::leftOutOf(s).empty() == all_paired, "what is left out is said exactly when something is");
  } catch (const risas::InputError&) {
  }
  if (!std::filesystem::exists(gt)) return;
  try {
    for (const risas::StampedPose& p : risas::readTumTrajectory(gt.string())) {
      require(std::isfinite(p.stamp) && isRigid(p.world_T_camera), "a trajectory's pose is a rigid motion");
    }
  } catch (const risas::InputError&) {
  }
}

// A features file as writeFeatures writes it (0 to 4 keypoints, with or
// without geometry and layout, YAML or JSON), then a few of its bytes
// changed, often to ones its syntax gives meaning, and now and then cut
// short: readFeatures either refuses it or gives features whose parts agree.
void fuzzFeaturesFile(Bytes& in) {
  static const FuzzFolder folder;
  const int n = in.in(0, 4), width = in.in(1, 8);
  risas::Features written;
  written.descriptors = cv::Mat(n, width, CV_32F);
  for (int i = 0; i < n; ++i) {
    written.keypoints.emplace_back(static_cast<float>(in.number(0, 640)), static_cast<float>(in.number(0, 480)), 10.0f);
    for (int j = 0; j < width; ++j) written.descriptors.at<float>(i, j) = static_cast<float>(in.number(0, 1));
  }
  if (in.byte() % 2) {
    for (int i = 0; i < n; ++i) {
      written.geometry.push_back({cv::Point3f(static_cast<float>(in.number(-1, 1)), 0.5f, 1.0f), cv::Vec3f(0, 0, -1),
                                  static_cast<float>(in.number(0, 0.1))});
    }
  }
  if (in.byte() % 2) written.descriptor_layout = "n_ring=1 n_pie=1 n_bin=1 n_vec=" + std::to_string(width - 1);
  const std::string path = (folder.path() / (in.byte() % 4 ? "features.yml" : "features.json")).string();
  risas::writeFeatures(path, written);
  std::string text;
  {
    std::ifstream file(path);
    text.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  }
  static const char kMeaningful[] = "0123456789-.e,:[]{}\" \nfdiu3";
  for (int k = in.in(0, 6); k > 0 && !text.empty(); --k) {
    const uint8_t b = in.byte();
    text[in.word() % text.size()] = b % 4 ? kMeaningful[b % (sizeof kMeaningful - 1)] : static_cast<char>(in.byte());
  }
  if (in.byte() % 8 == 0) text.resize(in.word() % (text.size() + 1));
  std::ofstream(path) << text;
  try {
    const risas::Features read = risas::readFeatures(path);
    const size_t count = read.keypoints.size();
    require(read.descriptors.rows == static_cast<int>(count), "one descriptor row per keypoint");
    require(count == 0 || read.descriptors.type() == CV_32F, "descriptors are CV_32F");
    require(read.geometry.empty() || read.geometry.size() == count, "geometry per keypoint");
  } catch (const risas::InputError&) {
  }
}

// The dataset's text files: R1-k.txt (a rotation about a random axis, now
// and then scaled or skewed), T1-k.txt and camera-intrinsics.txt, their
// numbers through numberText, now and then one too few or too many:
// readPoseFiles gives a rigid motion and readIntrinsicsFile a usable camera,
// or each refuses its file.
void fuzzDatasetTextFiles(Bytes& in) {
  static const FuzzFolder folder;
  const auto numbers = [&](const std::vector<double>& ordinary) {
    std::string text;
    const int count = static_cast<int>(ordinary.size()) + (in.byte() % 16 == 0 ? in.in(-2, 2) : 0);
    for (int i = 0; i < count; ++i) {
      text += numberText(in, ordinary[static_cast<size_t>(i) % ordinary.size()]) + (i % 3 == 2 ? "\n" : " ");
    }
    return text;
  };
  Eigen::Vector3d axis = Eigen::Vector3d::Constant(1e-3);
  for (int k = 0; k < 3; ++k) axis(k) += in.number(-1, 1);  // one at a time: arguments' order is unspecified
  const double angle = in.number(-4, 4);
  Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  if (in.byte() % 8 == 0) {  // near or beyond the tolerance
    const int row = in.in(0, 2), col = in.in(0, 2);
    R(row, col) += in.number(-0.01, 0.01);
  }
  const std::filesystem::path rotation = folder.path() / "R1-2.txt", translation = folder.path() / "T1-2.txt",
                              intrinsics = folder.path() / "camera-intrinsics.txt";
  std::ofstream(rotation) << numbers({R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)});
  std::ofstream(translation) << numbers({in.number(-2, 2), in.number(-2, 2), in.number(-2, 2)});
  std::ofstream(intrinsics) << numbers({in.number(-10, 900), 0, in.number(-10, 700), 0, in.number(-10, 900),
                                        in.number(-10, 500), 0, 0, 1});
  try {
    const Eigen::Isometry3d T = risas::readPoseFiles(rotation.string(), translation.string());
    const Eigen::Matrix3d read = T.linear();
    require(T.matrix().allFinite() && (read.transpose() * read - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-3 &&
                read.determinant() > 0.0,
            "a pose file's motion is rigid");
  } catch (const risas::InputError&) {
  }
  try {
    const risas::Intrinsics K = risas::readIntrinsicsFile(intrinsics.string());
    require(K.fx > 0.0 && K.fy > 0.0 && std::isfinite(K.fx) && std::isfinite(K.fy) && std::isfinite(K.cx) &&
                std::isfinite(K.cy),
            "an intrinsics file's camera has finite, positive focal lengths");
  } catch (const risas::InputError&) {
  }
}

// A colour image file, JPEG or PNG, encoded whole and then now and then cut
// short, its bytes overwritten or bytes inserted, read with a good depth
// image by readRgbdImages: it gives images of the kinds it promises or
// refuses the file; a whole file gives its decoding; a JPEG cut short is
// refused (OpenCV would return it grey where its data ran out) and a cut
// PNG is refused or read whole.
void fuzzImageFiles(Bytes& in) {
  static const FuzzFolder folder;
  const cv::Size size(in.in(1, 48), in.in(1, 48));
  const cv::Mat colour = image(in, size, CV_8UC3);
  const bool jpeg = in.byte() % 2;
  std::vector<uint8_t> encoded;
  require(cv::imencode(jpeg ? ".jpg" : ".png", colour, encoded), "an image encodes");
  std::string bytes(encoded.begin(), encoded.end());
  const std::string whole = bytes;
  const auto position = [&](size_t end) { return static_cast<size_t>(in.in(0, static_cast<int>(end))); };
  const int change = in.byte() % 4;  // 0: whole
  if (change == 1) bytes.resize(position(bytes.size() - 1));
  for (int k = change == 2 ? in.in(1, 8) : 0; k > 0; --k) {
    bytes[position(bytes.size() - 1)] = static_cast<char>(in.byte());
  }
  if (change == 3) {
    const size_t at = position(bytes.size());
    bytes.insert(at, std::string(static_cast<size_t>(in.in(1, 8)), static_cast<char>(in.byte())));
  }
  const std::string rgb = (folder.path() / (jpeg ? "colour.jpg" : "colour.png")).string();
  const std::string depth = (folder.path() / "depth.png").string();
  std::ofstream(rgb, std::ios::binary) << bytes;
  if (!std::filesystem::exists(depth)) cv::imwrite(depth, cv::Mat(4, 4, CV_16UC1, cv::Scalar(1000)));
  try {
    const risas::RgbdImages read = risas::readRgbdImages(rgb, depth);
    require(!read.bgr.empty() && read.bgr.type() == CV_8UC3 && read.depth_mm.type() == CV_16UC1,
            "images read are of the kinds promised");
    require(!(change == 1 && jpeg), "a JPEG cut short is refused");
    if (bytes == whole || change == 1) {
      const cv::Mat decoded = cv::imdecode(encoded, cv::IMREAD_COLOR);
      require(read.bgr.size() == decoded.size() && cv::norm(read.bgr, decoded, cv::NORM_INF) == 0.0,
              "a whole or cut file read gives the whole file's image");
    }
  } catch (const risas::InputError&) {
    require(bytes != whole, "a whole file is read");
  }
}

void fuzzParams(Bytes& in) {
  if (in.byte() % 2) {  // a parameter file, with or without its "%YAML" line, through load
    static const FuzzFolder folder;
    const std::string path = (folder.path() / "params.yml").string();
    std::ofstream(path, std::ios::binary) << (in.byte() % 2 ? "%YAML:1.0\n" : "") << in.rest();
    const auto one_line_naming = [&](const std::string& what, const std::string& start) {
      return what.rfind(start + path, 0) == 0 && what.find('\n') == std::string::npos;
    };
    try {
      risas::RisasParams::load(path);  // validates, the fields against each other too
    } catch (const std::runtime_error& e) {
      require(one_line_naming(e.what(), "cannot parse parameter file ") ||
                  one_line_naming(e.what(), "cannot read parameter file "),  // corrupt gzip
              "a parse or read error is one line naming the file");
    } catch (const std::invalid_argument& e) {
      require(one_line_naming(e.what(), "parameter file "), "a bad field is one line naming the file");
    }
    return;
  }
  const std::string text = "%YAML:1.0\n" + in.rest();
  cv::FileStorage fs;
  try {
    fs.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const std::exception&) {
    return;  // not FileStorage text: OpenCV's parser says so (now and then by std::length_error)
  }
  if (!fs.isOpened()) return;
  risas::RisasParams p;
  try {
    p.read(fs.root());
    p.validate();
  } catch (const risas::InputError&) {
  } catch (const cv::Exception&) {
    // FileStorage parses lazily: a malformed node can throw when it is read.
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  runCase([&] {
    switch (in.byte() % 7) {
      case 0: fuzzFrame(in); break;
      case 1: fuzzMatchingAndMotion(in); break;
      case 2: fuzzTumFolder(in); break;
      case 3: fuzzFeaturesFile(in); break;
      case 4: fuzzDatasetTextFiles(in); break;
      case 5: fuzzImageFiles(in); break;
      default: fuzzParams(in); break;
    }
  });
  return 0;
}

#include "risas/params.hpp"

#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace risas {
namespace {

// Each parameter struct lists its fields once, with their valid range, in
// visitFields(); writing, reading and validating are visitors over that list,
// so the three can never disagree about a name or a range.

template <class V>
void visitFields(GeometryParams& p, V&& v) {
  v("normal_radius", p.normal_radius, 1, 50);
  v("depth_change_factor", p.depth_change_factor, 1e-4, 1.0);
  v("min_normal_points", p.min_normal_points, 3, 10000);
}

template <class V>
void visitFields(DetectorParams& p, V&& v) {
  v("tau", p.tau, 0.0, 1.0);
  v("n_s", p.n_s, 2, 64);
  v("harris_k", p.harris_k, 0.0, 0.25);
  v("gray_sigma", p.gray_sigma, 0.0, 20.0);
  v("dp_sigma", p.dp_sigma, 0.0, 20.0);
  v("window_sigma", p.window_sigma, 0.3, 20.0);
  v("response_threshold", p.response_threshold, 0.0, 1.0);
  v("nms_radius", p.nms_radius, 1, 50);
  v("max_keypoints", p.max_keypoints, 1, 100000);
  v("grid_cols", p.grid_cols, 1, 256);
  v("grid_rows", p.grid_rows, 1, 256);
  v("border", p.border, 0, 1000);
}

template <class V>
void visitFields(DescriptorParams& p, V&& v) {
  v("gamma", p.gamma, 0.0, 1.0);
  v("n_pie", p.n_pie, 1, 64);
  v("n_bin", p.n_bin, 1, 256);
  v("n_vec", p.n_vec, 1, 64);
  v("rho_threshold", p.rho_threshold, 0.0, 1.0);
  v("support_radius", p.support_radius, 0.0, 1.0);
  v("background_distance", p.background_distance, 1e-3, 10.0);
  v("patch_radius", p.patch_radius, 4, 100);
  v("min_radius_px", p.min_radius_px, 1.0, 1000.0);
  v("max_radius_px", p.max_radius_px, 1.0, 1000.0);
  v("min_valid_fraction", p.min_valid_fraction, 0.0, 1.0);
  v("min_projection_angle_deg", p.min_projection_angle_deg, 0.0, 90.0);
}

template <class V>
void visitFields(MatchParams& p, V&& v) {
  v("ratio", p.ratio, 1e-6, 1.0);
  v("cross_check", p.cross_check);
}

template <class V>
void visitFields(MotionParams& p, V&& v) {
  v("inlier_threshold", p.inlier_threshold, 1e-6, 100.0);
  v("max_iterations", p.max_iterations, 1, 10000000);
  v("confidence", p.confidence, 0.0, 1.0);
  v("min_inliers", p.min_inliers, 3, 1000000);
  v("seed", p.seed, 0u, 0xffffffffu);
}

struct Validator {
  const char* section;
  template <class T>
  void operator()(const char* name, const T& value, T lo, T hi) const {
    if (!(value >= lo && value <= hi)) {
      std::ostringstream msg;
      msg << section << "." << name << " = " << value << " is outside [" << lo << ", " << hi << "]";
      throw std::invalid_argument(msg.str());
    }
  }
  void operator()(const char*, bool) const {}
};

struct Writer {
  cv::FileStorage& fs;
  template <class T>
  void operator()(const char* name, const T& value, T, T) const {
    if constexpr (std::is_same_v<T, unsigned int>) {
      fs << name << static_cast<int>(value);  // FileStorage has no unsigned type
    } else {
      fs << name << value;
    }
  }
  void operator()(const char* name, bool value) const { fs << name << static_cast<int>(value); }
};

struct Reader {
  const cv::FileNode& node;
  template <class T>
  void operator()(const char* name, T& value, T, T) const {
    const cv::FileNode field = node[name];
    if (field.empty()) return;  // absent: keep the default
    if (!field.isReal() && !field.isInt()) {
      throw std::invalid_argument(std::string("parameter ") + name + " is not a number");
    }
    if constexpr (std::is_integral_v<T>) {
      value = static_cast<T>(static_cast<int>(field));
    } else {
      value = static_cast<T>(static_cast<double>(field));
    }
  }
  void operator()(const char* name, bool& value) const {
    const cv::FileNode field = node[name];
    if (field.empty()) return;
    value = static_cast<int>(field) != 0;
  }
};

template <class P>
void validateFields(const P& params, const char* section) {
  P copy = params;
  visitFields(copy, Validator{section});
}

template <class P>
void writeFields(const P& params, cv::FileStorage& fs, const char* section) {
  P copy = params;
  fs << section << "{";
  visitFields(copy, Writer{fs});
  fs << "}";
}

template <class P>
void readFields(P& params, const cv::FileNode& node) {
  if (node.empty()) return;
  if (!node.isMap()) throw std::invalid_argument("parameter section " + node.name() + " is not a map");
  visitFields(params, Reader{node});
}

}  // namespace

void GeometryParams::validate() const { validateFields(*this, "geometry"); }
void GeometryParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "geometry"); }
void GeometryParams::read(const cv::FileNode& node) { readFields(*this, node); }

void DetectorParams::validate() const { validateFields(*this, "detector"); }
void DetectorParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "detector"); }
void DetectorParams::read(const cv::FileNode& node) { readFields(*this, node); }

void DescriptorParams::validate() const {
  validateFields(*this, "descriptor");
  if (min_radius_px > max_radius_px) {
    throw std::invalid_argument("descriptor.min_radius_px exceeds descriptor.max_radius_px");
  }
}
void DescriptorParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "descriptor"); }
void DescriptorParams::read(const cv::FileNode& node) { readFields(*this, node); }

void MatchParams::validate() const { validateFields(*this, "match"); }
void MatchParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "match"); }
void MatchParams::read(const cv::FileNode& node) { readFields(*this, node); }

void MotionParams::validate() const { validateFields(*this, "motion"); }
void MotionParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "motion"); }
void MotionParams::read(const cv::FileNode& node) { readFields(*this, node); }

void RisasParams::validate() const {
  geometry.validate();
  detector.validate();
  descriptor.validate();
  match.validate();
  motion.validate();
}

void RisasParams::write(cv::FileStorage& fs) const {
  geometry.write(fs);
  detector.write(fs);
  descriptor.write(fs);
  match.write(fs);
  motion.write(fs);
}

void RisasParams::read(const cv::FileNode& root) {
  geometry.read(root["geometry"]);
  detector.read(root["detector"]);
  descriptor.read(root["descriptor"]);
  match.read(root["match"]);
  motion.read(root["motion"]);
}

RisasParams RisasParams::load(const std::string& path) {
  RisasParams params;
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) throw std::runtime_error("cannot open parameter file " + path);
    params.read(fs.root());
  } catch (const cv::Exception& e) {
    throw std::runtime_error("cannot parse parameter file " + path + ": " + e.msg);
  }
  params.validate();
  return params;
}

void RisasParams::save(const std::string& path) const {
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  if (!fs.isOpened()) throw std::runtime_error("cannot write parameter file " + path);
  write(fs);
}

}  // namespace risas

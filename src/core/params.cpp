#include "risas/params.hpp"

#include "risas/params_fields.hpp"

#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace risas {
namespace {

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
  RisasParams copy = *this;
  visitSections(copy, [](const char*, const auto& section) { section.validate(); });
}

void RisasParams::write(cv::FileStorage& fs) const {
  RisasParams copy = *this;
  visitSections(copy, [&fs](const char*, const auto& section) { section.write(fs); });
}

void RisasParams::read(const cv::FileNode& root) {
  visitSections(*this, [&root](const char* name, auto& section) { section.read(root[name]); });
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

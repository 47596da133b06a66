#include "risas/params.hpp"

#include "risas/params_fields.hpp"

#include "risas/errors.hpp"
#include "risas/io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <locale>
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
      throw InputError(msg.str());
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

// Reads the fields present in a section's node; absent ones keep their
// values. A value is checked before it is converted (1e20 into an int would
// not be 1e20) and a whole-number field takes no fraction.
struct Reader {
  const cv::FileNode& node;
  const char* section;
  std::string where(const char* name) const { return std::string(section) + "." + name; }
  template <class T>
  void operator()(const char* name, T& value, T lo, T hi) const {
    const cv::FileNode field = node[name];
    if (field.empty()) return;  // absent: keep the default
    if (!field.isReal() && !field.isInt()) throw InputError(where(name) + " is not a number");
    const double read = static_cast<double>(field);
    if (!(read >= static_cast<double>(lo) && read <= static_cast<double>(hi))) {
      std::ostringstream msg;
      msg << where(name) << " = " << read << " is outside [" << lo << ", " << hi << "]";
      throw InputError(msg.str());
    }
    if constexpr (std::is_integral_v<T>) {
      if (read != std::floor(read)) {
        std::ostringstream msg;
        msg << where(name) << " = " << read << " is not a whole number";
        throw InputError(msg.str());
      }
    }
    value = static_cast<T>(read);
  }
  void operator()(const char* name, bool& value) const {
    const cv::FileNode field = node[name];
    if (field.empty()) return;
    const bool number = field.isInt() || field.isReal();
    const double read = number ? static_cast<double>(field) : -1.0;
    if (read != 0.0 && read != 1.0) throw InputError(where(name) + " is a flag: 0 or 1");
    value = read != 0.0;
  }
};

// The names a section's visitor knows.
struct NameCollector {
  std::vector<std::string>& names;
  template <class T>
  void operator()(const char* name, const T&, T, T) const { names.emplace_back(name); }
  void operator()(const char* name, bool) const { names.emplace_back(name); }
};

// InputError naming the first key of `node` that is not in `known`: a typo
// in a parameter file would otherwise leave the default silently in place.
void rejectUnknownKeys(const cv::FileNode& node, const std::vector<std::string>& known, const std::string& what,
                       const std::string& prefix) {
  for (const cv::FileNode& key : node) {
    const std::string name = key.name();
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    throw InputError("unknown " + what + " '" + prefix + name + "' (known: " + list + ")");
  }
}

// cv::Exception's message without its "OpenCV(4.x) file:line: error: (code)"
// prefix and trailing newline: what the parser says, in one line.
std::string parserReason(const cv::Exception& e) {
  std::string m = e.msg;
  const size_t error = m.find("error: (");
  const size_t close = error == std::string::npos ? std::string::npos : m.find(") ", error);
  if (close != std::string::npos) m = m.substr(close + 2);
  std::replace(m.begin(), m.end(), '\n', ' ');
  while (!m.empty() && m.back() == ' ') m.pop_back();
  // "<what> in function '<where>'": FileStorage's parser puts the file, line
  // and reason in the second part and its own name in the first.
  const size_t in_function = m.find(" in function '");
  if (in_function != std::string::npos) {
    const std::string what = m.substr(0, in_function);
    std::string where = m.substr(in_function + 14);
    if (!where.empty() && where.back() == '\'') where.pop_back();
    m = where.find("): ") != std::string::npos ? where : what;
  }
  return m.empty() ? e.err : m;
}

// OpenCV 4.6's FileStorage reads YAML only after a "%YAML" line; rosparam,
// PyYAML and later OpenCV read it without one. The text of a parameter file
// that begins with none of FileStorage's signatures ("%YAML", '{' of JSON,
// '<' of XML, after a UTF-8 byte order mark) gets that line put in front.
// Returns whether it did.
bool withYamlDirective(std::string& text) {
  const size_t start = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  if (text.compare(start, 5, "%YAML") == 0 || text.compare(start, 1, "{") == 0 || text.compare(start, 1, "<") == 0) {
    return false;
  }
  text.insert(start, "%YAML:1.0\n");
  return true;
}

// A parser reason of text read from memory, "(N): reason", as the file's:
// "path(N - added_lines): reason".
std::string reasonInFile(const std::string& reason, const std::string& path, int added_lines) {
  int line = 0;
  char rest = 0;
  if (std::sscanf(reason.c_str(), "(%d%c", &line, &rest) == 2 && rest == ')') {
    return path + "(" + std::to_string(line - added_lines) + reason.substr(reason.find(')'));
  }
  return reason;
}

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
void readFields(P& params, const cv::FileNode& node, const char* section) {
  if (node.empty() || node.isNone()) return;
  if (!node.isMap()) throw InputError(std::string("parameter section ") + section + " is not a map of names to values");
  std::vector<std::string> names;
  P copy = params;
  visitFields(copy, NameCollector{names});
  rejectUnknownKeys(node, names, "parameter", std::string(section) + ".");
  visitFields(params, Reader{node, section});
}

}  // namespace

void GeometryParams::validate() const { validateFields(*this, "geometry"); }
void GeometryParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "geometry"); }
void GeometryParams::read(const cv::FileNode& node) { readFields(*this, node, "geometry"); }

void DetectorParams::validate() const { validateFields(*this, "detector"); }
void DetectorParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "detector"); }
void DetectorParams::read(const cv::FileNode& node) { readFields(*this, node, "detector"); }

std::string DescriptorParams::layout() const {
  std::ostringstream out;
  out.imbue(std::locale::classic());  // a decimal point whatever the global locale
  out << "n_ring=" << n_ring << " n_pie=" << n_pie << " n_bin=" << n_bin << " n_vec=" << n_vec;
  if (ownShapeHistogram()) out << " shape_weight=" << shape_weight;  // six significant digits, as %g
  return out.str();
}

void DescriptorParams::validate() const {
  validateFields(*this, "descriptor");
  if (min_radius_px > max_radius_px) {
    throw InputError("descriptor.min_radius_px exceeds descriptor.max_radius_px");
  }
  if (ownShapeHistogram() && n_vec < 1) {
    throw InputError("descriptor.shape_weight > 0 needs descriptor.n_vec >= 1: it weighs the shape labels' histogram");
  }
  if (dimension() > kMaxDimension) {
    const std::string formula =
        ownShapeHistogram() ? "n_ring * n_pie * (n_bin + n_vec + 1)" : "n_ring * n_pie * n_bin * (n_vec + 1)";
    throw InputError("descriptor size " + formula + " = " + std::to_string(dimension()) + " exceeds " +
                     std::to_string(kMaxDimension) + " (" + layout() + "): a patch of " + std::to_string(patch_radius) +
                     " samples per radius cannot fill so many bins");
  }
}
void DescriptorParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "descriptor"); }
void DescriptorParams::read(const cv::FileNode& node) { readFields(*this, node, "descriptor"); }

void MatchParams::validate() const { validateFields(*this, "match"); }
void MatchParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "match"); }
void MatchParams::read(const cv::FileNode& node) { readFields(*this, node, "match"); }

void MotionParams::validate() const { validateFields(*this, "motion"); }
void MotionParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "motion"); }
void MotionParams::read(const cv::FileNode& node) { readFields(*this, node, "motion"); }

void OdometryParams::validate() const { validateFields(*this, "odometry"); }
void OdometryParams::write(cv::FileStorage& fs) const { writeFields(*this, fs, "odometry"); }
void OdometryParams::read(const cv::FileNode& node) { readFields(*this, node, "odometry"); }

void RisasParams::validate() const {
  RisasParams copy = *this;
  visitSections(copy, [](const char*, const auto& section) { section.validate(); });
}

void RisasParams::write(cv::FileStorage& fs) const {
  RisasParams copy = *this;
  visitSections(copy, [&fs](const char*, const auto& section) { section.write(fs); });
}

void RisasParams::read(const cv::FileNode& root) {
  if (root.empty() || root.isNone()) return;
  if (!root.isMap()) throw InputError("parameters must be a map of sections (geometry, detector, ...)");
  std::vector<std::string> sections;
  visitSections(*this, [&sections](const char* name, auto&) { sections.emplace_back(name); });
  rejectUnknownKeys(root, sections, "parameter section", "");
  visitSections(*this, [&root](const char* name, auto& section) { section.read(root[name]); });
}

RisasParams RisasParams::load(const std::string& path) {
  std::string text;
  try {
    text = readTextFile(path, "parameter file");  // gzip too, as FileStorage reads it
  } catch (const InputError& e) {
    throw std::runtime_error(e.what());  // "cannot read parameter file P: <the system's reason>"
  }
  RisasParams params;
  int added_lines = 0;
  try {
    added_lines = withYamlDirective(text) ? 1 : 0;
    cv::FileStorage fs(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
    params.read(fs.root());
    params.validate();  // the fields' bounds on each other, which read cannot see one at a time
  } catch (const cv::Exception& e) {
    throw std::runtime_error("cannot parse parameter file " + path + ": " +
                             reasonInFile(parserReason(e), path, added_lines));
  } catch (const InputError& e) {
    throw InputError("parameter file " + path + ": " + e.what());
  } catch (const std::exception& e) {
    // OpenCV's parser lets a standard exception out on some corrupt files
    // (std::length_error on a key that begins with ':').
    throw std::runtime_error("cannot parse parameter file " + path + ": OpenCV's parser failed (" + e.what() + ")");
  }
  return params;
}

void RisasParams::save(const std::string& path) const {
  // Into memory (the format from the name), then written whole or refused.
  cv::FileStorage fs(path, cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  write(fs);
  writeTextFile(path, fs.releaseAndGetString(), "parameter file");
}

}  // namespace risas

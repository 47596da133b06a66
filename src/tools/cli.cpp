#include "cli.hpp"

#include "risas/errors.hpp"
#include "risas/io.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace risas::cli {
namespace {

double parseNumber(const std::string& name, const std::string& text) {
  std::istringstream in(text);
  double value = 0.0;
  if (!(in >> value) || !in.eof()) throw UsageError("--" + name + " expects a number, got '" + text + "'");
  return value;
}

// `text` as a whole number within [lo, hi], checked before any cast (so
// 1e20 is refused, not cast); UsageError naming the option otherwise.
int parseWholeNumber(const std::string& name, const std::string& text, int lo, int hi) {
  const double value = parseNumber(name, text);
  if (!(value >= lo && value <= hi) || value != std::floor(value)) {
    throw UsageError("--" + name + " must be a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "], got '" + text + "'");
  }
  return static_cast<int>(value);
}

}  // namespace

Args::Args(int argc, char** argv, const std::string& synopsis, std::vector<Option> options) {
  options.push_back({"help", "", "print this help and exit"});
  const auto find = [&](const std::string& name) -> const Option* {
    for (const Option& o : options) {
      if (o.name == name) return &o;
    }
    return nullptr;
  };
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.rfind("--", 0) != 0) throw UsageError("unexpected argument '" + arg + "'");
    arg = arg.substr(2);
    std::string value;
    const size_t eq = arg.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
    }
    const Option* option = find(arg);
    if (!option) throw UsageError("unknown option --" + arg);
    if (option->value_name.empty()) {
      if (inline_value) throw UsageError("--" + arg + " takes no value");
      value = "1";
    } else if (!inline_value) {
      // The next word is the value unless it is one of the tool's options:
      // "--intrinsics --out F" has lost its value, and taking "--out" for it
      // would blame F instead.
      const std::string next = i + 1 < argc ? argv[i + 1] : "";
      const std::string next_name = next.rfind("--", 0) == 0 ? next.substr(2, next.find('=') - 2) : "";
      if (i + 1 >= argc || (!next_name.empty() && find(next_name))) {
        throw UsageError("--" + arg + " needs a value (" + option->value_name + ")" +
                         (i + 1 < argc ? ", not the option " + next : ""));
      }
      value = argv[++i];
    }
    // Given twice, one of the two would be dropped in silence.
    const auto [given, first] = values_.emplace(arg, value);
    if (!first) {
      throw UsageError("--" + arg + " is given twice" +
                       (option->value_name.empty() ? "" : " ('" + given->second + "', then '" + value + "')"));
    }
  }
  if (has("help")) {
    std::cout << synopsis << "\n\nOptions:\n";
    for (const Option& o : options) {
      const std::string left = "--" + o.name + (o.value_name.empty() ? "" : " " + o.value_name);
      std::cout << "  " << std::left << std::setw(28) << left << o.help << "\n";
    }
    std::exit(0);
  }
}

std::string Args::get(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) throw UsageError("missing --" + name);
  return it->second;
}

std::string Args::get(const std::string& name, const std::string& fallback) const {
  return has(name) ? get(name) : fallback;
}

double Args::getDouble(const std::string& name) const { return parseNumber(name, get(name)); }

double Args::getDouble(const std::string& name, double fallback) const {
  return has(name) ? getDouble(name) : fallback;
}

int Args::getInt(const std::string& name, int fallback, int lo, int hi) const {
  return has(name) ? parseWholeNumber(name, get(name), lo, hi) : fallback;
}

std::vector<std::string> Args::getList(const std::string& name, const std::string& fallback) const {
  const std::string list = get(name, fallback);
  std::vector<std::string> items;
  size_t start = 0;
  while (true) {
    const size_t comma = list.find(',', start);
    const std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (item.empty()) throw UsageError("--" + name + " has an empty item in '" + list + "'");
    if (std::find(items.begin(), items.end(), item) != items.end()) {
      throw UsageError("--" + name + " names '" + item + "' twice");
    }
    items.push_back(item);
    if (comma == std::string::npos) return items;
    start = comma + 1;
  }
}

std::vector<int> Args::getIntList(const std::string& name, const std::string& fallback, int lo, int hi) const {
  std::vector<int> numbers;
  for (const std::string& item : getList(name, fallback)) {
    const int number = parseWholeNumber(name, item, lo, hi);
    // Written two ways ("1,01"), getList's check does not see it.
    if (std::find(numbers.begin(), numbers.end(), number) != numbers.end()) {
      throw UsageError("--" + name + " names " + std::to_string(number) + " twice");
    }
    numbers.push_back(number);
  }
  return numbers;
}

void Args::refuse(const std::vector<std::string>& names, const std::string& context) const {
  for (const std::string& name : names) {
    if (has(name)) throw UsageError("--" + name + " does not apply " + context);
  }
}

std::vector<Option> intrinsicsOptions() {
  return {{"intrinsics", "K.txt", "3x3 camera matrix in text (the dataset's camera-intrinsics.txt)"},
          {"fx", "F", "focal length x in pixels (instead of --intrinsics)"},
          {"fy", "F", "focal length y in pixels"},
          {"cx", "C", "principal point x in pixels"},
          {"cy", "C", "principal point y in pixels"}};
}

std::vector<std::string> intrinsicsOptionNames() {
  std::vector<std::string> names;
  for (const Option& o : intrinsicsOptions()) names.push_back(o.name);
  return names;
}

Option depthUnitsOption() {
  return {"depth-units", "N", "16-bit depth values a metre: 1000 = millimetres (default: OpenNI, ROS, the dataset), 5000 = TUM RGB-D"};
}

double depthUnitsFrom(const Args& args) { return args.getDouble("depth-units", kMillimetreDepthUnits); }

Option paramsOption() { return {"params", "P.yml", "parameter file (cv::FileStorage; see config/risas.yaml)"}; }

Intrinsics intrinsicsFrom(const Args& args) {
  const bool numbers = args.has("fx") || args.has("fy") || args.has("cx") || args.has("cy");
  if (args.has("intrinsics")) {
    // Both ways at once would leave one of them unused, in silence.
    if (numbers) throw UsageError("give --intrinsics K.txt or --fx --fy --cx --cy, not both");
    return readIntrinsicsFile(args.get("intrinsics"));
  }
  if (!numbers) throw UsageError("give --intrinsics K.txt or --fx --fy --cx --cy");
  Intrinsics K(args.getDouble("fx"), args.getDouble("fy"), args.getDouble("cx"), args.getDouble("cy"));
  K.validate();
  return K;
}

Intrinsics intrinsicsGivenOrFound(const Args& args, const std::string& dir) {
  const std::vector<std::string> names = intrinsicsOptionNames();
  const bool given = std::any_of(names.begin(), names.end(), [&](const std::string& name) { return args.has(name); });
  return given ? intrinsicsFrom(args) : findIntrinsics(dir);
}

void writeMatrixFile(const std::string& path, const Eigen::MatrixXd& m) {
  std::ostringstream out;
  out << std::setprecision(12);
  for (int r = 0; r < m.rows(); ++r) {
    for (int c = 0; c < m.cols(); ++c) out << (c ? " " : "") << m(r, c);
    out << "\n";
  }
  writeTextFile(path, out.str(), "matrix file");
}

void writeIntrinsicsFile(const std::string& path, const Intrinsics& K) {
  const cv::Matx33d matrix = K.matrix();
  writeMatrixFile(path, Eigen::Matrix3d(Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(matrix.val)));
}

RisasParams paramsFrom(const Args& args) {
  return args.has("params") ? RisasParams::load(args.get("params")) : RisasParams();
}

void requireWritable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path file = fs::absolute(path, ec);
  const fs::path dir = file.parent_path();
  if (!fs::is_directory(dir, ec)) throw InputError("cannot write " + path + ": no folder " + dir.string());
  if (fs::is_directory(file, ec)) throw InputError("cannot write " + path + ": it is a folder");
  const bool exists = fs::exists(file, ec);
  if (::access((exists ? file : dir).c_str(), W_OK) != 0) {
    throw InputError("cannot write " + path + ": " + (exists ? "the file" : "its folder") + " is not writable");
  }
}

TumSequence readTumSequenceNoting(const char* tool, const std::string& dir, double truth_offset) {
  TumSequence sequence = readTumSequence(dir, kTumMaxDifference, truth_offset);
  const std::string left_out = leftOutOf(sequence);
  if (!left_out.empty()) std::cerr << tool << ": " << dir << ": " << left_out << ": left out\n";
  return sequence;
}

void makeOutputFolder(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(dir, ec)) return;
  if (fs::exists(dir, ec)) throw InputError("cannot make folder " + dir + ": a file of that name is there");
  fs::create_directories(dir, ec);
  if (ec) throw InputError("cannot make folder " + dir + ": " + ec.message());
}

int runTool(const char* tool, const std::function<int()>& body) {
  try {
    const int code = body();
    // What a tool prints is its result too: standard output on a full disk
    // is a failure, not a success.
    errno = 0;
    if (!std::cout.flush()) {
      throw InputError(std::string("cannot write standard output") + (errno ? std::string(": ") + std::strerror(errno) : ""));
    }
    return code;
  } catch (const UsageError& e) {
    std::cerr << tool << ": " << e.what() << " (see " << tool << " --help)\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
    return 1;
  }
}

std::string scriptPath(const std::string& name) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  std::vector<fs::path> candidates;
  if (!error) candidates.push_back(self.parent_path() / RISAS_SCRIPTS_FROM_BIN / name);
  candidates.push_back(fs::path(RISAS_SOURCE_SCRIPTS) / name);
  for (const fs::path& candidate : candidates) {
    if (fs::is_regular_file(candidate, error)) return fs::weakly_canonical(candidate, error).string();
  }
  return "";
}

}  // namespace risas::cli

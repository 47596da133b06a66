// What the command-line tools share: option parsing with --help, reading a
// frame and parameters from options, and turning errors into exit codes.
#pragma once

#include "risas/intrinsics.hpp"
#include "risas/params.hpp"
#include "risas/rgbd_frame.hpp"
#include "risas/tum_sequence.hpp"

#include <Eigen/Core>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace risas::cli {

struct Option {
  std::string name;  // without the leading --
  std::string value_name;  // empty for a flag
  std::string help;
};

// Thrown for wrong usage; runTool prints it with a hint to --help, exit 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Args {
 public:
  // Accepts --name value and --name=value, each option once; --help prints
  // the usage and exits 0.
  Args(int argc, char** argv, const std::string& synopsis, std::vector<Option> options);

  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string get(const std::string& name) const;  // UsageError when missing
  std::string get(const std::string& name, const std::string& fallback) const;
  double getDouble(const std::string& name) const;
  double getDouble(const std::string& name, double fallback) const;
  // A whole number within [lo, hi]: UsageError naming the option and the
  // range otherwise (checked before any cast, so 1e20 is refused, not cast).
  int getInt(const std::string& name, int fallback, int lo, int hi) const;
  // A comma-separated list ("viewchange,illum"), `fallback` when not given:
  // UsageError for an empty item ("a,,b") or one given twice, which would
  // be dropped or run twice in silence.
  std::vector<std::string> getList(const std::string& name, const std::string& fallback) const;
  // getList's items as whole numbers, each within [lo, hi] (UsageError as
  // getInt's otherwise) and each once ("1,01" is refused too).
  std::vector<int> getIntList(const std::string& name, const std::string& fallback, int lo, int hi) const;
  // UsageError naming the first of `names` that is given: an option that
  // does not apply in the tool's mode (`context`, e.g. "with --data") would
  // be ignored in silence.
  void refuse(const std::vector<std::string>& names, const std::string& context) const;

 private:
  std::map<std::string, std::string> values_;
};

// The intrinsics given as --intrinsics K.txt or as --fx --fy --cx --cy (not
// both).
Intrinsics intrinsicsFrom(const Args& args);
// The intrinsics given as above if any of their options is, else the
// camera-intrinsics.txt at or above the dataset folder `dir` (findIntrinsics).
Intrinsics intrinsicsGivenOrFound(const Args& args, const std::string& dir);
// --params P.yml if given, else the defaults.
RisasParams paramsFrom(const Args& args);
// --depth-units N if given (16-bit depth values a metre), else millimetres.
double depthUnitsFrom(const Args& args);
// The options intrinsicsFrom, depthUnitsFrom and paramsFrom read, for a
// tool's option list.
std::vector<Option> intrinsicsOptions();
std::vector<std::string> intrinsicsOptionNames();
Option depthUnitsOption();
Option paramsOption();

// `m` as text, a row a line, numbers to 12 digits: the dataset's R1-k.txt,
// T1-k.txt and camera-intrinsics.txt, which readMatrixFile reads back.
// InputError when it cannot be written (writeTextFile).
void writeMatrixFile(const std::string& path, const Eigen::MatrixXd& m);
// K's 3x3 matrix so, as camera-intrinsics.txt (readIntrinsicsFile).
void writeIntrinsicsFile(const std::string& path, const Intrinsics& K);

// InputError unless `path` can be written: its folder exists and is
// writable, and the file, if there, is too. Tools check their outputs with
// it before the work, not after.
void requireWritable(const std::string& path);

// The recording `dir` as readTumSequence reads it (its ground truth's
// stamps shifted by truth_offset seconds); what the association left out
// (leftOutOf) printed as a note, "<tool>: <dir>: ...: left out", on
// standard error.
TumSequence readTumSequenceNoting(const char* tool, const std::string& dir, double truth_offset = 0.0);

// Makes the folder `dir` and its parents unless `dir` is a folder already;
// InputError "cannot make folder D: <reason>" otherwise (a file in the way).
void makeOutputFolder(const std::string& dir);

// The path of scripts/<name> for this tool: installed beside it (the
// package's share/risas/scripts, found from the executable's own path), else
// in the source tree it was built from; empty when neither has it.
std::string scriptPath(const std::string& name);

// Runs the body; prints errors as "<tool>: error: ..." and returns the exit
// code: 0 ok, 1 failure (bad input, unreadable files), 2 wrong usage.
int runTool(const char* tool, const std::function<int()>& body);

}  // namespace risas::cli

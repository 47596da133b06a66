// The command-line tools run as a user runs them, for the tests that check
// what they print and how they exit.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace risas::test {

struct ToolRun {
  int exit_code;
  std::string output;  // standard output and errors together
};

// The whole text of the file at `path` ("" when it cannot be read).
inline std::string fileText(const std::filesystem::path& path) {
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  return text.str();
}

// RISAS_BIN_DIR/<command_line> in sh; `shell` runs before it in the same
// shell (a limit for the tool alone: "ulimit -f 512; exec ").
inline ToolRun runTool(const std::string& command_line, const std::string& shell = "") {
  namespace fs = std::filesystem;
  const fs::path log = fs::temp_directory_path() / ("risas_tool_" + std::to_string(::getpid()) + ".log");
  const int status = std::system(
      (shell + std::string(RISAS_BIN_DIR) + "/" + command_line + " > " + log.string() + " 2>&1").c_str());
  const std::string output = fileText(log);
  fs::remove(log);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// /dev/full under `path`: it opens, and every write to it fails as on a
// full disk.
inline std::string fullDiskAt(const std::filesystem::path& path) {
  std::filesystem::remove(path);
  std::filesystem::create_symlink("/dev/full", path);
  return path.string();
}

}  // namespace risas::test

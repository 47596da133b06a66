// risas_fuzz_loop, risas_ros_fuzz_loop: a fuzz driver without libFuzzer
// (any compiler). Feeds LLVMFuzzerTestOneInput random inputs from a seed
// until a time budget or a count runs out, then prints how many it ran. A
// broken invariant or a sanitizer report aborts the process.
//
//   risas_fuzz_loop [--seconds S] [--runs N] [--seed K] [--max-len L] [FILE...]
//
// Files given are run once each first (a corpus, or a crash to reproduce).
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int main(int argc, char** argv) {
  const std::string name = std::filesystem::path(argv[0]).filename().string();
  double seconds = 10.0;
  long runs = -1;
  unsigned seed = 1;
  size_t max_len = 4096;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "risas_fuzz_loop: " << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--seconds") seconds = std::stod(value());
    else if (a == "--runs") runs = std::stol(value());
    else if (a == "--seed") seed = static_cast<unsigned>(std::stoul(value()));
    else if (a == "--max-len") max_len = std::stoul(value());
    else if (a.rfind("--", 0) == 0) {
      std::cerr << name << ": unknown option " << a << "\n";
      return 2;
    } else files.push_back(a);
  }
  for (const std::string& f : files) {
    std::ifstream in(f, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  }
  std::mt19937 rng(seed);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  long done = 0;
  std::vector<uint8_t> input;
  while ((runs < 0 || done < runs) && std::chrono::steady_clock::now() < end) {
    // Lengths spread over the range, bytes often small (sizes, choices).
    input.resize(rng() % (max_len + 1));
    for (uint8_t& b : input) b = static_cast<uint8_t>(rng() % 4 ? rng() : rng() % 8);
    LLVMFuzzerTestOneInput(input.data(), input.size());
    ++done;
  }
  std::cout << name << ": " << done << " inputs (seed " << seed << "), no invariant broken\n";
  return 0;
}

#include "risas/ranking.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace risas {

void rankGroupTable(const int* histogram, int levels, int groups, uint8_t* table) {
  int64_t total = 0;
  for (int v = 0; v < levels; ++v) total += histogram[v];
  // below is the running count. The group, below * groups / total rounded
  // down, only grows with below: it is stepped, not divided for.
  int64_t below = 0, group = 0, next = total;  // next: where group + 1 starts, times groups
  for (int v = 0; v < levels; ++v) {
    // Levels above the highest counted one reach below == total, one group
    // past the last; they hold no value, and the last group keeps every
    // label a valid index.
    while (total && below * groups >= next && group < groups - 1) ++group, next += total;
    table[v] = static_cast<uint8_t>(group);
    below += histogram[v];
  }
}

namespace {

// The weights of the values within reach of a level v, reach = ceil(4 s),
// in units of 1 / kUnit: weight[j] = Phi((reach - j) / s) for the value at
// level v - reach + j, j = 0 .. 2 reach, so that a level's sum runs forward
// over the histogram and the weights alike, in integers (which the compiler
// sums in vectors; floats it must add in order). Each thread keeps the table
// of the last s it was asked for (one frame's noise, one s).
constexpr int kUnit = 1 << 14;
constexpr int kMaxValues = std::numeric_limits<int>::max() / kUnit;  // 131,071
struct NoiseKernel {
  float s = -1.0f;
  int reach = 0;
  std::vector<int> weight;
};

const NoiseKernel& noiseKernel(float s) {
  thread_local NoiseKernel kernel;
  if (kernel.s != s) {
    kernel.s = s;
    kernel.reach = static_cast<int>(std::ceil(4.0f * s));
    kernel.weight.resize(static_cast<size_t>(2 * kernel.reach + 1));
    for (int j = 0; j <= 2 * kernel.reach; ++j) {
      const double phi = 0.5 * std::erfc(-(kernel.reach - j) / (static_cast<double>(s) * std::sqrt(2.0)));
      kernel.weight[static_cast<size_t>(j)] = static_cast<int>(std::lround(phi * kUnit));
    }
  }
  return kernel;
}

}  // namespace

void rankPositionTable(const int* histogram, int levels, int groups, float noise, uint8_t* lower,
                       float* upper_weight) {
  int total = 0;
  for (int v = 0; v < levels; ++v) total += histogram[v];
  // position = (2 below + histogram[v]) * groups / (2 total) - 1/2, with the
  // division taken once; clamped to the end groups without a branch. Under
  // noise, 2 below + histogram[v] becomes twice the expected mid-rank.
  const float scale = total ? static_cast<float>(groups) / static_cast<float>(2 * total) : 0.0f;
  const int last = groups - 1;
  const NoiseKernel* kernel = noise > 0.0f ? &noiseKernel(std::sqrt(2.0f) * noise) : nullptr;
  CV_Assert(!kernel || total <= kMaxValues);
  const int reach = kernel ? kernel->reach : 0;
  int below = 0;       // the values under level v
  int far_below = 0;   // the values under level v - reach: they count whole
  for (int v = 0; v < levels; ++v) {
    float twice_mid_rank = static_cast<float>(2 * below + histogram[v]);
    if (kernel && histogram[v] > 0) {
      // The values within reach, each Phi of its distance below v.
      const int first = std::max(v - reach, 0), end = std::min(v + reach + 1, levels);
      const int* weight = kernel->weight.data() + (first - (v - reach));
      int within = 0;  // in units of 1 / kUnit; below 2^31 for up to kMaxValues values
      for (int w = first; w < end; ++w) within += histogram[w] * weight[w - first];
      twice_mid_rank = 2.0f * (static_cast<float>(far_below) + static_cast<float>(within) / kUnit);
    }
    const float position = twice_mid_rank * scale - 0.5f;
    const int group = std::min(std::max(static_cast<int>(position), 0), last);  // truncation: -0.5 .. 0 -> 0
    const float weight = position - static_cast<float>(group);
    lower[v] = static_cast<uint8_t>(group);
    upper_weight[v] = group < last ? std::min(std::max(weight, 0.0f), 1.0f) : 0.0f;
    below += histogram[v];
    if (v >= reach) far_below += histogram[v - reach];
  }
}

void rankGroups(const std::vector<uint16_t>& values, int levels, int groups, std::vector<uint8_t>& labels) {
  std::vector<int> histogram(static_cast<size_t>(levels), 0);
  for (uint16_t v : values) {
    CV_Assert(v < levels);
    ++histogram[v];
  }
  std::vector<uint8_t> table(static_cast<size_t>(levels));
  rankGroupTable(histogram.data(), levels, groups, table.data());
  labels.resize(values.size());
  for (size_t i = 0; i < values.size(); ++i) labels[i] = table[values[i]];
}

}  // namespace risas

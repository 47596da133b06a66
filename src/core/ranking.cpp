#include "risas/ranking.hpp"

#include <opencv2/core.hpp>

#include <algorithm>

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

void rankPositionTable(const int* histogram, int levels, int groups, uint8_t* lower, float* upper_weight) {
  int total = 0;
  for (int v = 0; v < levels; ++v) total += histogram[v];
  // position = (2 below + histogram[v]) * groups / (2 total) - 1/2, with the
  // division taken once; clamped to the end groups without a branch.
  const float scale = total ? static_cast<float>(groups) / static_cast<float>(2 * total) : 0.0f;
  const int last = groups - 1;
  int below = 0;
  for (int v = 0; v < levels; ++v) {
    const float position = static_cast<float>(2 * below + histogram[v]) * scale - 0.5f;
    const int group = std::min(std::max(static_cast<int>(position), 0), last);  // truncation: -0.5 .. 0 -> 0
    const float weight = position - static_cast<float>(group);
    lower[v] = static_cast<uint8_t>(group);
    upper_weight[v] = group < last ? std::min(std::max(weight, 0.0f), 1.0f) : 0.0f;
    below += histogram[v];
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

#include "risas/ranking.hpp"

#include <opencv2/core.hpp>

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

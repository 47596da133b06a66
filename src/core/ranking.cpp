#include "risas/ranking.hpp"

#include <opencv2/core.hpp>

namespace risas {

void ranksBelow(const int* histogram, int levels, int* below) {
  int seen = 0;
  for (int v = 0; v < levels; ++v) {
    below[v] = seen;
    seen += histogram[v];
  }
}

void rankGroups(const std::vector<uint16_t>& values, int levels, int groups, std::vector<uint8_t>& labels) {
  std::vector<int> histogram(static_cast<size_t>(levels), 0), below(static_cast<size_t>(levels));
  for (uint16_t v : values) {
    CV_Assert(v < levels);
    ++histogram[v];
  }
  ranksBelow(histogram.data(), levels, below.data());
  labels.resize(values.size());
  const int64_t n = static_cast<int64_t>(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    labels[i] = static_cast<uint8_t>(static_cast<int64_t>(below[values[i]]) * groups / n);
  }
}

}  // namespace risas

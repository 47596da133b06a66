#include "risas/ranking.hpp"

#include <opencv2/core.hpp>

namespace risas {

void ranks(const std::vector<uint16_t>& values, int levels, std::vector<int>& out) {
  std::vector<int> below(static_cast<size_t>(levels) + 1, 0);
  for (uint16_t v : values) {
    CV_Assert(v < levels);
    ++below[v + 1];
  }
  for (int l = 1; l <= levels; ++l) below[l] += below[l - 1];  // below[v] = #values < v
  out.resize(values.size());
  for (size_t i = 0; i < values.size(); ++i) out[i] = below[values[i]];
}

void rankGroups(const std::vector<uint16_t>& values, int levels, int groups, std::vector<uint8_t>& labels) {
  std::vector<int> r;
  ranks(values, levels, r);
  labels.resize(values.size());
  const int64_t n = static_cast<int64_t>(values.size());
  for (size_t i = 0; i < values.size(); ++i) labels[i] = static_cast<uint8_t>(static_cast<int64_t>(r[i]) * groups / n);
}

}  // namespace risas

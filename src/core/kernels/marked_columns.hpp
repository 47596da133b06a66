// Internal to the core: visiting the few marked columns of a row.
#pragma once

#include <cstdint>
#include <cstring>

namespace risas {

// Calls visit(u) for each u in [begin, end) with marks[u] != 0, passing over
// eight unmarked columns at a time: for rows where few are marked, a test
// per column costs more than the visits. marks must be readable up to
// end + 7.
template <class Visit>
void forEachMarked(const unsigned char* marks, int begin, int end, Visit&& visit) {
  for (int u = begin; u < end; ++u) {
    uint64_t eight;
    std::memcpy(&eight, marks + u, sizeof eight);
    if (eight == 0) {
      u += 7;
      continue;
    }
    if (marks[u]) visit(u);
  }
}

}  // namespace risas

// Ordinal statistics by counting sort: what makes RISAS illumination
// invariant. Any monotonic intensity change keeps every rank (ties aside).
#pragma once

#include <cstdint>
#include <vector>

namespace risas {

// The rank group of every level from the histogram of the values:
// table[v] = below[v] * groups / count, `groups` groups of equal size, where
// below[v] (the rank of v) counts the values strictly below v, so equal
// values share a rank. O(levels), whatever the count.
// Every entry lies in [0, groups), also for levels no value has.
// histogram and table hold `levels` entries; groups in [1, 256].
void rankGroupTable(const int* histogram, int levels, int groups, uint8_t* table);

// Ranks cut into `groups` groups of equal size: group = rank * groups / count.
// Values must lie in [0, levels). Ties share the lower group
// (docs/method.md says why).
void rankGroups(const std::vector<uint16_t>& values, int levels, int groups, std::vector<uint8_t>& labels);

}  // namespace risas

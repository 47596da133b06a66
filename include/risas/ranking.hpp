// Ordinal statistics by counting sort: what makes RISAS illumination
// invariant. Any monotonic intensity change keeps every rank (ties aside).
#pragma once

#include <cstdint>
#include <vector>

namespace risas {

// Rank of each value: how many values lie strictly below it, so equal values
// share a rank. Values must lie in [0, levels). O(count + levels).
void ranks(const std::vector<uint16_t>& values, int levels, std::vector<int>& out);

// Ranks cut into `groups` groups of equal size: group = rank * groups / count.
// (Giving ties their run's middle rank instead was measured worse under the
// paper's intensity transforms.)
void rankGroups(const std::vector<uint16_t>& values, int levels, int groups, std::vector<uint8_t>& labels);

}  // namespace risas

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

// Soft rank groups, for descriptor.soft_binning: each level's mid-rank
// (below[v] + histogram[v] / 2) as a position among the group centres,
// position = mid-rank * groups / count - 1/2. A value of level v votes
// 1 - upper_weight[v] for group lower[v] and upper_weight[v] for group
// lower[v] + 1, so a value that moves across a group boundary moves its vote
// gradually instead of all at once. Below the first centre and above the last
// the whole vote stays in the end group (upper_weight 0); lower[v] + 1 is a
// group whenever upper_weight[v] > 0. An empty histogram gives group 0.
//
// noise > 0 (descriptor.grey_noise): the values carry noise of that
// standard deviation, so the order of two values is only as sure as their
// difference is against the noise of a difference, s = sqrt(2) noise. A
// level that holds values then takes its expected mid-rank under the noise,
// sum over w of histogram[w] Phi((v - w) / s), where Phi, the normal
// distribution function, is 1/2 at 0 (a tie counts half, as the mid-rank's)
// and is taken as 0 or 1 beyond 4 s (within 3.2e-5 of it). Values further
// apart than the noise keep their order as at noise 0; values within it
// share their rank in proportion to how sure it is, so that the noise moves
// their votes little. Levels no value holds keep the exact mid-rank (no
// value reads them). The weights Phi are taken in steps of 2^-14, so the
// histogram may hold at most 131,071 values under noise (a patch holds a
// few hundred to a few thousand). noise 0: the exact mid-rank.
void rankPositionTable(const int* histogram, int levels, int groups, float noise, uint8_t* lower,
                       float* upper_weight);

// Ranks cut into `groups` groups of equal size: group = rank * groups / count.
// Values must lie in [0, levels). Ties share the lower group
// (docs/method.md says why).
void rankGroups(const std::vector<uint16_t>& values, int levels, int groups, std::vector<uint8_t>& labels);

}  // namespace risas

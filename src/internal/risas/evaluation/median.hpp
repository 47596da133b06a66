// The median the evaluation and the tools report: of alignment errors over
// a scene, of a trajectory's position errors, of RANSAC seeds' ATEs, of a
// benchmark's repeats.
#pragma once

#include <vector>

namespace risas::eval {

// The middle value of `values`, the mean of the two middle ones for an even
// count; InputError when there are none. Linear time.
double median(std::vector<double> values);

}  // namespace risas::eval

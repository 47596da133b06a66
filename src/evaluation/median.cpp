#include "risas/evaluation/median.hpp"

#include "risas/errors.hpp"

#include <algorithm>
#include <cstddef>

namespace risas::eval {

double median(std::vector<double> values) {
  if (values.empty()) throw InputError("the median of no values");
  const size_t half = values.size() / 2;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(half);
  std::nth_element(values.begin(), middle, values.end());  // linear: the pose error's 19,200 points a seed
  if (values.size() % 2) return *middle;
  return 0.5 * (*std::max_element(values.begin(), middle) + *middle);  // the lower middle one precedes it
}

}  // namespace risas::eval

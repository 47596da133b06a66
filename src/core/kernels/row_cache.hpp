// Internal to the core: rows of an image made on demand, for passes down an
// image that read a few neighbouring rows at a time.
#pragma once

#include <algorithm>
#include <climits>
#include <vector>

namespace risas {

// Float rows made on demand and kept in `slots` slots, row i in slot
// i % slots: any `slots` consecutive rows are held at once, so a filter
// down the columns whose taps span no more than that reads each row made
// once, without the whole image in memory.
class RowCache {
 public:
  // Forgets every row (a new image); rows of cols floats.
  void reset(int cols, int slots) {
    pitch_ = static_cast<size_t>(cols);
    data_.resize(pitch_ * static_cast<size_t>(slots));
    tags_.assign(static_cast<size_t>(slots), INT_MIN);
  }
  // Row i, made by make(i, out) if it is not held.
  template <class Make>
  const float* row(int i, Make&& make) {
    const size_t slot = static_cast<size_t>(i % static_cast<int>(tags_.size()));
    float* out = data_.data() + slot * pitch_;
    if (tags_[slot] != i) {
      make(i, out);
      tags_[slot] = i;
    }
    return out;
  }

 private:
  size_t pitch_ = 0;
  std::vector<float> data_;
  std::vector<int> tags_;
};

}  // namespace risas

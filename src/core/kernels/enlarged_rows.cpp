#include "enlarged_rows.hpp"

#include "risas/params.hpp"

#include "vector_clones.hpp"
#include "with_default.hpp"

#include <algorithm>

namespace risas {
namespace {

// A grid row enlarged stride times along the row: output x = j stride + k is
// (1 - a[k]) row[j + o[k]] + a[k] row[j + o[k] + 1]; row[-1] and
// row[grid_cols] repeat the ends, which clamps as cv::resize does. Stride is
// an int or, for the default, a compile-time constant: the loop over phases
// then unrolls and the loop over blocks vectorises.
template <class Stride>
RISAS_VECTOR_CLONES
void enlargeRow(const float* row, int grid_cols, Stride stride, const int* o, const float* a, float* __restrict out) {
  for (int j = 0; j < grid_cols; ++j) {
    for (int k = 0; k < stride; ++k) {
      out[j * stride + k] = (1.0f - a[k]) * row[j + o[k]] + a[k] * row[j + o[k] + 1];
    }
  }
}

// out = (1 - b) above + b below: a row between two enlarged rows.
RISAS_VECTOR_CLONES
void blendRows(const float* above, const float* below, float b, int cols, float* __restrict out) {
  for (int x = 0; x < cols; ++x) out[x] = (1.0f - b) * above[x] + b * below[x];
}

}  // namespace

void EnlargedRows::reset(const cv::Mat& grid, int stride, cv::Size size) {
  CV_Assert(grid.type() == CV_32FC1 && !grid.empty() && stride >= 1);
  CV_Assert(size.width <= grid.cols * stride && size.height <= grid.rows * stride);
  grid_ = &grid, stride_ = stride, size_ = size;
  o_.resize(static_cast<size_t>(stride));
  a_.resize(static_cast<size_t>(stride));
  for (int k = 0; k < stride; ++k) {
    const float f = (static_cast<float>(k) + 0.5f) / static_cast<float>(stride) - 0.5f;
    o_[static_cast<size_t>(k)] = f < 0.0f ? -1 : 0;
    a_[static_cast<size_t>(k)] = f - static_cast<float>(o_[static_cast<size_t>(k)]);
  }
  padded_.resize(static_cast<size_t>(grid.cols) + 2);
  along_.reset(grid.cols * stride, 2);  // a row blends two consecutive ones
  finished_.reset(size.width, 3);
}

void EnlargedRows::enlargeAlong(int i, float* out) {
  const float* row = grid_->ptr<float>(i);
  padded_.front() = row[0];
  std::copy(row, row + grid_->cols, padded_.begin() + 1);
  padded_.back() = row[grid_->cols - 1];
  withDefault<GeometryParams::kDefaultNormalStride>(stride_, [&](auto stride) {
    enlargeRow(padded_.data() + 1, grid_->cols, stride, o_.data(), a_.data(), out);
  });
}

const float* EnlargedRows::row(int y) {
  return finished_.row(y, [&](int, float* out) {
    const int k = y % stride_, i = y / stride_ + o_[static_cast<size_t>(k)], last = grid_->rows - 1;
    const auto along = [&](int row) { return along_.row(row, [&](int r, float* o) { enlargeAlong(r, o); }); };
    const float* above = along(std::clamp(i, 0, last));
    const float* below = along(std::clamp(i + 1, 0, last));
    blendRows(above, below, a_[static_cast<size_t>(k)], size_.width, out);
  });
}

}  // namespace risas

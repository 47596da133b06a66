// Internal to the core: a grid image enlarged bilinearly, row by row.
#pragma once

#include "row_cache.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace risas {

// The rows of a grid image (CV_32FC1) enlarged stride times, bilinearly, to
// `size` (at most stride - 1 pixels short of whole blocks: partial blocks at
// the right and bottom), made one at a time on demand: a pass down the
// image reads them without the enlarged image. Pixel (x, y) samples the grid
// at ((x + 0.5) / stride - 0.5, (y + 0.5) / stride - 0.5), clamped to the
// grid's edges, along the rows first and then down the columns, as
// cv::resize's INTER_LINEAR does. One object per thread; reset per image,
// which must outlive the rows' use (it is not held).
class EnlargedRows {
 public:
  void reset(const cv::Mat& grid, int stride, cv::Size size);
  const float* row(int y);  // y in [0, size.height); size.width floats, any three at once

 private:
  void enlargeAlong(int i, float* out);
  const cv::Mat* grid_ = nullptr;
  int stride_ = 1;
  cv::Size size_;
  // Each phase k of a block: the grid sample (k + 0.5) / stride - 0.5 lies
  // between offsets o[k] and o[k] + 1 from the block, at weight a[k].
  std::vector<int> o_;
  std::vector<float> a_, padded_;
  RowCache along_, finished_;
};

}  // namespace risas

#include "risas/grey_noise.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace risas {

double estimateGreyNoise(const cv::Mat& gray) {
  CV_Assert(gray.type() == CV_8UC1);
  if (gray.rows < 3 || gray.cols < 3) return 0.0;
  // The mask is the outer product of [1 -2 1] with itself: each row's
  // vertical second differences first, then their horizontal ones, summed
  // in runs short enough for an int (at most 16 * 255 a pixel).
  constexpr int kRun = 4096;
  std::vector<int> vertical(static_cast<size_t>(gray.cols));
  int64_t sum = 0;
  for (int y = 1; y + 1 < gray.rows; ++y) {
    const uchar* above = gray.ptr<uchar>(y - 1);
    const uchar* row = gray.ptr<uchar>(y);
    const uchar* below = gray.ptr<uchar>(y + 1);
    int* d = vertical.data();
    for (int x = 0; x < gray.cols; ++x) d[x] = above[x] - 2 * row[x] + below[x];
    for (int start = 1; start + 1 < gray.cols; start += kRun) {
      const int end = std::min(start + kRun, gray.cols - 1);
      int run_sum = 0;
      for (int x = start; x < end; ++x) run_sum += std::abs(d[x - 1] - 2 * d[x] + d[x + 1]);
      sum += run_sum;
    }
  }
  const double pixels = static_cast<double>(gray.rows - 2) * static_cast<double>(gray.cols - 2);
  return std::sqrt(CV_PI / 2.0) * static_cast<double>(sum) / (6.0 * pixels);
}

}  // namespace risas

// Internal to the core: loops over interleaved points four at a time, for
// OpenCV's universal intrinsics (cv::v_load_deinterleave into x, y, z lanes).
#pragma once

#include <opencv2/core.hpp>

#include <algorithm>

namespace risas {

// Calls f(xyz, i) for i = 0, 4, 8, ... < count, xyz pointing at the 12
// floats of points[i .. i + 3]. The last call's points beyond count are
// `padding`, read from a copy: nothing past points[count - 1] is read.
template <class F>
void inFours(const cv::Vec3f* points, int count, const cv::Vec3f& padding, F&& f) {
  int i = 0;
  for (; i + 4 <= count; i += 4) f(&points[i][0], i);
  if (i < count) {
    cv::Vec3f tail[4] = {padding, padding, padding, padding};
    std::copy(points + i, points + count, tail);
    f(&tail[0][0], i);
  }
}

}  // namespace risas

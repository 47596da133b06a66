// Internal to the core: the Gaussian filters of the detector (the grey blur,
// eq. 1's window w) and of the dot-product image, all cut at 3 sigma.
#pragma once

#include "row_cache.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace risas {

// The kernel's size cut at 3 sigma, as OpenCV itself does for 8-bit images
// (its float default, 4 sigma, adds taps of < 0.3 % of the weight).
cv::Size gaussianSize(double sigma);

// The kernel as its centre weight and the weights of the offsets 1 .. radius
// (it is symmetric): OpenCV's float kernel, cut at 3 sigma.
std::vector<float> gaussianHalfKernel(double sigma);

// The radii of the defaults, which have compiled loops (withDefault):
// window_sigma 1.5 has radius 5; dp_sigma 5 on the normals' default stride 2
// (2.5 on their grid) radius 8; gray_sigma 1 radius 3.
constexpr int kDefaultWindowRadius = 5, kDefaultDotProductRadius = 8, kDefaultGrayRadius = 3;

// cv::borderInterpolate for the two borders the filters use
// (cv::BORDER_REPLICATE and cv::BORDER_REFLECT_101), inline: the filters ask
// for it per row and tap, and OpenCV's is a call into its library.
inline int borderIndex(int p, int len, int border) {
  if (static_cast<unsigned>(p) < static_cast<unsigned>(len)) return p;
  if (border == cv::BORDER_REPLICATE || len == 1) return p < 0 ? 0 : len - 1;
  do {
    p = p < 0 ? -p : 2 * len - 2 - p;
  } while (static_cast<unsigned>(p) >= static_cast<unsigned>(len));
  return p;
}

// The symmetric filter: out[u] = half[0] taps[radius][u] + the sum over
// t = 1 .. radius of half[t] (taps[radius - t][u] + taps[radius + t][u]).
// Along a row, taps[i] is the row shifted by i - radius; down the columns,
// the row at that offset. Radius is an int or one of the default radii as a
// compile-time constant (std::integral_constant, from withDefault).
template <class Radius>
void symmetricWindow(const float* const* taps, const float* half, Radius radius, int cols, float* out);

// The rows of src (CV_8UC1 or CV_32FC1) filtered with `half` along the
// rows and down the columns, the border extrapolated by `border`
// (cv::BORDER_REPLICATE or cv::BORDER_REFLECT_101, as cv::borderInterpolate),
// made one at a time on demand: a pass down the image reads them without a
// blurred copy of the image. Rows filtered along are kept while the taps
// down the columns reach them, finished rows while three neighbours are read.
// One object per thread; reset per image, which must outlive the rows' use
// (it is not held).
class BlurredRows {
 public:
  void reset(const cv::Mat& src, const std::vector<float>& half, int border);
  const float* row(int v);  // v in [0, src.rows)

 private:
  void filterAlong(int v, float* out);
  const cv::Mat* src_ = nullptr;
  std::vector<float> half_, padded_;
  std::vector<const float*> along_taps_, column_taps_;
  int border_ = 0;
  RowCache along_, finished_;
};

}  // namespace risas

// The fast kernel of gradientOrientation; see gradient_orientation.hpp for
// the contract. The grid is axis-aligned: each column has one place in the
// image and one bilinear cell column on each pyramid level, and each row
// likewise, found once (Axis). Row by row, the values a row needs are
// gathered into arrays and the arithmetic runs over the arrays in loops that
// vectorise; the background's reach is looked for only where there is
// background, each row's voters are one word of bits, and the votes'
// directions come in one vectorised call.
#include "gradient_orientation.hpp"

#include "risas/orientation_histogram.hpp"
#include "risas/workspace.hpp"

#include "vector_clones.hpp"

#include <opencv2/core/hal/hal.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace risas {
namespace {

// Where the grid's columns (or rows) fall along one image axis: the
// samples' coordinate, whether it lies in the image, its nearest pixel
// (clamped into the image), and on each of the (up to two) pyramid levels
// greyAt blends, the first pixel of its bilinear cell and the second
// pixel's weight, as greyAt clamps them.
struct Axis {
  std::vector<uint8_t> inside;
  std::vector<int> nearest;
  std::vector<int> first[2];
  std::vector<float> second_weight[2];
};

// The samples centre + spacing k, k = -half .. half, along an axis of `size`
// pixels; level_size[m] pixels along it on the m-th level read, at
// level_scale[m] of level 0's coordinates.
void placeAxis(float centre, float spacing, int half, int size, const int* level_size, const float* level_scale,
               int levels_read, Axis& axis) {
  const size_t count = static_cast<size_t>(2 * half + 1);
  axis.inside.resize(count);
  axis.nearest.resize(count);
  for (int m = 0; m < levels_read; ++m) {
    axis.first[m].resize(count);
    axis.second_weight[m].resize(count);
  }
  for (int k = -half; k <= half; ++k) {
    const size_t s = static_cast<size_t>(k + half);
    const float x = centre + spacing * static_cast<float>(k);
    axis.inside[s] = x >= 0.0f && x <= static_cast<float>(size - 1);
    axis.nearest[s] = static_cast<int>(std::nearbyint(std::clamp(x, 0.0f, static_cast<float>(size - 1))));
    for (int m = 0; m < levels_read; ++m) {
      const float xc = std::clamp(x * level_scale[m], 0.0f, static_cast<float>(level_size[m] - 1));
      const int first = std::min(static_cast<int>(xc), level_size[m] - 2);
      axis.first[m][s] = first;
      axis.second_weight[m][s] = xc - static_cast<float>(first);
    }
  }
}

// One thread's buffers, kept from keypoint to keypoint.
struct OrientationBuffers {
  Axis columns, rows;
  std::vector<float> x_factor;               // per column, at its nearest pixel
  std::vector<int> normal_index;             // per column, its block normal's z in a row of normals
  std::vector<float> z, normal_z;            // one row's gathered depth and block normal z
  std::vector<uint8_t> on_surface;           // one row's gathered surface flags
  std::vector<float> at_first, at_second;    // one level row's pixels gathered at the grid's columns
  std::vector<float> along[2][2];            // per level read, its two rows' values along them
  int along_row[2] = {-1, -1};               // the level row along[m][0] holds (along[m][1]: the next)
  std::vector<float> level_grey;             // one row's values on the coarser level
  std::vector<SampleKind> kind;              // the grid, row by row
  std::vector<float> grey;
  std::vector<uint64_t> background, reach;   // a bit per column, per row: Background; Background within kBlurReach
  std::vector<uint64_t> counted;             // a bit per column, per row: Counted
  std::vector<float> gx, gy, degrees;
  std::vector<double> gaussian, weight;
  int gaussian_radius = -1;                  // the disc radius gaussian was made for
};

// One row's kinds from its gathered values: Background outside the image
// or beyond t of k_i, Uncounted without depth or a normal, else Counted.
RISAS_VECTOR_CLONES
void classifyRow(int count, const uint8_t* inside, const float* x_factor, float y_factor, const float* z,
                 const uint8_t* on_surface, const float* normal_z, float kx, float ky, float kz, float t2,
                 SampleKind* kind) {
  for (int i = 0; i < count; ++i) {
    const float dx = x_factor[i] * z[i] - kx, dy = y_factor * z[i] - ky, dz = z[i] - kz;
    const bool has_point = z[i] == z[i];
    const bool near = dx * dx + dy * dy + dz * dz < t2;
    const bool normal = (on_surface[i] != 0) & (normal_z[i] != 0.0f);
    // Without branches: Background 2, Uncounted 1, Counted 0.
    const int background = (inside[i] == 0) | (has_point & !near);
    const int uncounted = (background == 0) & (!has_point | !normal);
    kind[i] = static_cast<SampleKind>(2 * background + uncounted);
  }
}

// One level row's values between its pixels `first` and first + 1 at the
// grid's columns: greyAt's bilinear, along the row.
RISAS_VECTOR_CLONES
void alongRow(int count, const float* a, const float* at_first, const float* at_second, float* out) {
  for (int i = 0; i < count; ++i) out[i] = (1.0f - a[i]) * at_first[i] + a[i] * at_second[i];
}

// Between two level rows' values: greyAt's bilinear, across the rows.
RISAS_VECTOR_CLONES
void acrossRows(int count, float b, const float* upper, const float* lower, float* out) {
  for (int i = 0; i < count; ++i) out[i] = (1.0f - b) * upper[i] + b * lower[i];
}

// greyAt's blend of two levels' values, into finer.
RISAS_VECTOR_CLONES
void blendRow(int count, float fraction, const float* coarser, float* finer) {
  for (int i = 0; i < count; ++i) finer[i] = (1.0f - fraction) * finer[i] + fraction * coarser[i];
}

// Bit i set where kinds[i] is `kind`, i < count < 64: eight kinds at a
// time, each byte compared with `kind` and its equality bit gathered into
// one byte by a multiplication. Reads up to 7 bytes past kinds[count - 1]
// (the grid's next row, or kKindSlack), whose bits are masked off.
constexpr size_t kKindSlack = 8;
uint64_t kindBits(const SampleKind* kinds, int count, SampleKind kind) {
  static_assert(static_cast<int>(SampleKind::Background) < 4, "a kind's value fits its byte's two low bits");
  const uint64_t wanted = static_cast<uint64_t>(kind) * 0x0101010101010101ULL;
  uint64_t bits = 0;
  for (int i = 0; i < count; i += 8) {
    uint64_t word;
    std::memcpy(&word, kinds + i, sizeof word);
    const uint64_t differ = word ^ wanted;  // zero in a byte's two low bits where it is `kind`
    const uint64_t flags = ~(differ | differ >> 1) & 0x0101010101010101ULL;  // one bit a byte, little-endian order
    bits |= ((flags * 0x0102040810204080ULL) >> 56) << i;
  }
  return bits & ((uint64_t{1} << count) - 1);  // not the bytes past count
}

// Each row's bits widened by kBlurReach columns to each side.
uint64_t widened(uint64_t bits) {
  uint64_t out = bits;
  for (int d = 1; d <= kBlurReach; ++d) out |= bits << d | bits >> d;
  return out;
}

}  // namespace

bool gradientOrientationKernelFits(const DescriptorParams& params) {
  return 2 * (params.patch_radius + 1 + kBlurReach) + 1 < 64;  // a grid row's bits in one word
}

double gradientOrientationKernel(const GreyPyramid& grey, const FrameGeometry& geometry, const Neighbourhood& nb,
                                 float radius_px, const DescriptorParams& params) {
  CV_Assert(gradientOrientationKernelFits(params));
  const int n = params.patch_radius, half = n + 1 + kBlurReach, side = 2 * half + 1, read = n + 1;
  OrientationBuffers& b = Workspace::ofThisThread().get<OrientationBuffers>();
  const float spacing = radius_px / static_cast<float>(n);
  const float lambda = blurLevel(kOrientationBlur * spacing, grey.levels);
  const int level = static_cast<int>(lambda);
  const float fraction = lambda - static_cast<float>(level);
  const int levels_read = fraction == 0.0f ? 1 : 2;
  const float scale = std::ldexp(1.0f, -level);
  const float level_scale[2] = {scale, scale * 0.5f};
  int level_cols[2] = {0, 0}, level_rows[2] = {0, 0};
  for (int m = 0; m < levels_read; ++m) {
    level_cols[m] = grey.level[level + m].cols;
    level_rows[m] = grey.level[level + m].rows;
  }
  const cv::Size size = geometry.depth.size();
  placeAxis(nb.centre.x, spacing, half, size.width, level_cols, level_scale, levels_read, b.columns);
  placeAxis(nb.centre.y, spacing, half, size.height, level_rows, level_scale, levels_read, b.rows);
  const size_t columns = static_cast<size_t>(side);
  const int stride = geometry.normal_stride;
  b.x_factor.resize(columns);
  b.normal_index.resize(columns);
  for (size_t i = 0; i < columns; ++i) {
    b.x_factor[i] = geometry.x_factor[static_cast<size_t>(b.columns.nearest[i])];
    b.normal_index[i] = 3 * (b.columns.nearest[i] / stride) + 2;
  }
  for (auto* v : {&b.z, &b.normal_z, &b.at_first, &b.at_second, &b.level_grey}) v->resize(columns);
  for (int m = 0; m < 2; ++m) {
    b.along[m][0].resize(columns), b.along[m][1].resize(columns);
    b.along_row[m] = -1;
  }
  b.on_surface.resize(columns);
  b.kind.resize(columns * columns + kKindSlack);
  b.grey.resize(columns * columns);  // read only where written: counted samples within reach of the disc

  // Each row's kinds, and the grey of the rows and columns near the disc.
  const float kx = static_cast<float>(nb.point.x()), ky = static_cast<float>(nb.point.y()),
              kz = static_cast<float>(nb.point.z());
  const float t2 = static_cast<float>(params.background_distance * params.background_distance);
  const int first_read = half - read, read_count = 2 * read + 1;
  b.background.assign(columns, 0);
  b.counted.assign(columns, 0);
  // The row's gathers through local pointers: the byte stores would
  // otherwise make the compiler reload every vector's data pointer.
  const int* nearest_column = b.columns.nearest.data();
  const int* normal_index = b.normal_index.data();
  float* row_z = b.z.data();
  float* row_normal_z = b.normal_z.data();
  uint8_t* row_on_surface = b.on_surface.data();
  for (int j = 0; j < side; ++j) {
    const int v = b.rows.nearest[static_cast<size_t>(j)];
    const float* depth = geometry.depth.ptr<float>(v);
    const uchar* on_surface = geometry.on_block_surface.ptr<uchar>(v);
    const float* normals = geometry.normals.ptr<float>(v / stride);
    for (int i = 0; i < side; ++i) {
      const int u = nearest_column[i];
      row_z[i] = depth[u];
      row_on_surface[i] = on_surface[u];
      row_normal_z[i] = normals[normal_index[i]];
    }
    SampleKind* kinds = b.kind.data() + static_cast<size_t>(j) * columns;
    if (b.rows.inside[static_cast<size_t>(j)]) {
      classifyRow(side, b.columns.inside.data(), b.x_factor.data(), geometry.y_factor[static_cast<size_t>(v)],
                  b.z.data(), b.on_surface.data(), b.normal_z.data(), kx, ky, kz, t2, kinds);
    } else {
      std::fill(kinds, kinds + side, SampleKind::Background);
    }
    b.background[static_cast<size_t>(j)] = kindBits(kinds, side, SampleKind::Background);
    b.counted[static_cast<size_t>(j)] = kindBits(kinds, side, SampleKind::Counted);
    if (std::abs(j - half) > read) continue;
    float* greys = b.grey.data() + static_cast<size_t>(j) * columns + first_read;
    for (int m = 0; m < levels_read; ++m) {
      // Successive grid rows often fall between the same two level rows
      // (the level is coarser than the grid): their values along the rows
      // are kept and made again only when the rows change.
      const cv::Mat& image = grey.level[level + m];
      const int v0 = b.rows.first[m][static_cast<size_t>(j)];
      if (v0 != b.along_row[m]) {
        int r = 0;
        if (b.along_row[m] >= 0 && v0 == b.along_row[m] + 1) {  // one row on: the lower row becomes the upper
          std::swap(b.along[m][0], b.along[m][1]);
          r = 1;
        }
        for (; r < 2; ++r) {
          const uchar* pixels = image.ptr<uchar>(v0 + r);
          for (int i = 0; i < read_count; ++i) {
            const int u0 = b.columns.first[m][static_cast<size_t>(first_read + i)];
            b.at_first[static_cast<size_t>(i)] = pixels[u0];
            b.at_second[static_cast<size_t>(i)] = pixels[u0 + 1];
          }
          alongRow(read_count, b.columns.second_weight[m].data() + first_read, b.at_first.data(),
                   b.at_second.data(), b.along[m][r].data());
        }
        b.along_row[m] = v0;
      }
      acrossRows(read_count, b.rows.second_weight[m][static_cast<size_t>(j)], b.along[m][0].data(),
                 b.along[m][1].data(), m == 0 ? greys : b.level_grey.data());
    }
    if (levels_read == 2) blendRow(read_count, fraction, b.level_grey.data(), greys);
  }

  // Background within kBlurReach of each sample, in its row and then its
  // column: the rows' bits widened, then OR-ed over the rows within reach.
  // (The disc lies kBlurReach + 1 samples inside the grid's edge, which the
  // readable rule counts as background: no disc sample is that near it.)
  b.reach.assign(columns, 0);
  for (int j = 0; j < side; ++j) {
    const uint64_t row = widened(b.background[static_cast<size_t>(j)]);
    for (int d = std::max(0, j - kBlurReach); d <= std::min(side - 1, j + kBlurReach); ++d) b.reach[static_cast<size_t>(d)] |= row;
  }

  // The votes: gradients of the clear disc samples whose four neighbours
  // count, with their Gaussian weights; their directions in one call. Each
  // row's voters are one word of bits (the disc's span, clear of the
  // background, counted, and so are the neighbours left, right, above and
  // below), visited in the readable rule's order.
  if (b.gaussian_radius != n) {  // made once for the thread's patch_radius
    b.gaussian.resize(static_cast<size_t>(2 * n + 1));
    for (int i = -n; i <= n; ++i) b.gaussian[static_cast<size_t>(i + n)] = std::exp(-0.5 * i * i / (n * n));
    b.gaussian_radius = n;
  }
  const size_t most = columns * columns;
  for (auto* v : {&b.gx, &b.gy, &b.degrees}) v->resize(most);
  b.weight.resize(most);
  int count = 0;
  for (int j = -n; j <= n; ++j) {
    const int extent = static_cast<int>(std::sqrt(static_cast<double>(n * n - j * j)));  // the disc's half-width in this row
    const size_t row = static_cast<size_t>(j + half);
    const uint64_t disc = ((uint64_t{1} << (2 * extent + 1)) - 1) << (half - extent);
    const uint64_t here = b.counted[row];
    uint64_t voters = disc & ~b.reach[row] & here & here << 1 & here >> 1 & b.counted[row - 1] & b.counted[row + 1];
    const float* grey_row = b.grey.data() + row * columns;
    const double row_weight = b.gaussian[static_cast<size_t>(j + n)];
    for (; voters != 0; voters &= voters - 1) {
      const int column = __builtin_ctzll(voters);
      const float* g = grey_row + column;
      const float gx = g[1] - g[-1], gy = g[columns] - g[-static_cast<std::ptrdiff_t>(columns)];
      if (gx == 0.0f && gy == 0.0f) continue;
      b.gx[static_cast<size_t>(count)] = gx, b.gy[static_cast<size_t>(count)] = gy;
      b.weight[static_cast<size_t>(count)] =
          std::sqrt(gx * gx + gy * gy) * b.gaussian[static_cast<size_t>(column - half + n)] * row_weight;
      ++count;
    }
  }
  if (count > 0) cv::hal::fastAtan32f(b.gy.data(), b.gx.data(), b.degrees.data(), count, true);
  // Successive votes often fall into the same bins: four histograms, one
  // vote each in turn, keep the additions from waiting on each other. The
  // sum is the readable rule's in another order.
  OrientationHistogram partial[4] = {};
  for (int s = 0; s < count; ++s) {
    voteDirection(partial[s & 3], b.degrees[static_cast<size_t>(s)], b.weight[static_cast<size_t>(s)]);
  }
  OrientationHistogram histogram{};
  for (int bin = 0; bin < kOrientationBins; ++bin) {
    const size_t k = static_cast<size_t>(bin);
    histogram[k] = (partial[0][k] + partial[1][k]) + (partial[2][k] + partial[3][k]);
  }
  return histogramPeak(histogram);
}

}  // namespace risas

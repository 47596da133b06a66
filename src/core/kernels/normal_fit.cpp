// The fast kernel of the normals (estimateNormals, normals.cpp): the same
// fit from sliding box sums of the point moments in float, vectorised, in
// parallel bands. See normal_fit.hpp for the contract.
#include "normal_fit.hpp"

#include "risas/workspace.hpp"

#include "marked_columns.hpp"
#include "vector_clones.hpp"
#include "with_default.hpp"

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

namespace risas {
namespace {

// The moments of a window's points: count, sums of x, y, z and of their six
// products. All the covariance of a window needs, and additive, so the sums
// of a sliding window are kept by adding the entering points and subtracting
// the leaving ones. One array per moment, so that the loops along a row
// vectorise. In float (sixteen lanes with AVX-512, against eight in double),
// which holds: no sum spans more than a window (the box sums add a window's
// columns directly, no running sum along the row), and the points are taken
// about a reference near the band's points (covariances do not change with
// it), so E[xx] - E[x]^2 cancels few digits. Normals move by 0.01 degrees on
// average against sums in double, PR-AUC not at all.
enum Moment { kN, kX, kY, kZ, kXX, kXY, kXZ, kYY, kYZ, kZZ, kMoments };

class RowMoments {
 public:
  // Zeroed, room for `length` values per moment and `pad` zeros either side.
  void reset(int length, int pad) {
    length_ = length;
    pitch_ = (length + 2 * pad + 15) / 16 * 16;
    pad_ = pad;
    data_.assign(static_cast<size_t>(kMoments) * pitch_, 0.0f);
  }
  float* operator[](int moment) { return data_.data() + static_cast<size_t>(moment) * pitch_ + pad_; }
  const float* operator[](int moment) const { return data_.data() + static_cast<size_t>(moment) * pitch_ + pad_; }

  // Adds (sign 1) or removes (sign -1) the moments of one image row's points
  // (coordinates x, y, z, offset by -reference) where the mask is set,
  // column by column.
  RISAS_VECTOR_CLONES
  void accumulate(const float* x, const float* y, const float* z, const uchar* mask, float sign,
                  const cv::Vec3f& reference) {
    float* s[kMoments];
    for (int k = 0; k < kMoments; ++k) s[k] = (*this)[k];
    const float rx = reference[0], ry = reference[1], rz = reference[2];
#pragma GCC ivdep  // the moments' arrays are distinct
    for (int u = 0; u < length_; ++u) {
      // Loaded, then selected, not branched on; a masked-out point may be
      // NaN and is never multiplied.
      const bool in = mask[u] != 0;
      const float w = in ? sign : 0.0f;
      const float px = in ? x[u] - rx : 0.0f, py = in ? y[u] - ry : 0.0f, pz = in ? z[u] - rz : 0.0f;
      const float wx = w * px, wy = w * py, wz = w * pz;
      s[kN][u] += w;
      s[kX][u] += wx; s[kY][u] += wy; s[kZ][u] += wz;
      s[kXX][u] += wx * px; s[kXY][u] += wx * py; s[kXZ][u] += wx * pz;
      s[kYY][u] += wy * py; s[kYZ][u] += wy * pz; s[kZZ][u] += wz * pz;
    }
  }

 private:
  int length_ = 0, pitch_ = 0, pad_ = 0;
  std::vector<float> data_;
};

// A row's windows in the form the fit takes, the point count and the six
// entries of the covariance C = [a b c; b d e; c e f], and the fit's
// unoriented normal (nx, ny, nz): one array each.
struct RowCovariances {
  std::vector<float> n, a, b, c, d, e, f, nx, ny, nz;
  void resize(int cols) {
    for (std::vector<float>* v : {&n, &a, &b, &c, &d, &e, &f, &nx, &ny, &nz}) v->resize(static_cast<size_t>(cols));
  }
  void set(int u, float n_, float x, float y, float z, float xx, float xy, float xz, float yy, float yz, float zz) {
    const float inv = n_ > 0.0f ? 1.0f / n_ : 0.0f;
    const float mx = x * inv, my = y * inv, mz = z * inv;
    n[u] = n_;
    a[u] = xx * inv - mx * mx;
    b[u] = xy * inv - mx * my;
    c[u] = xz * inv - mx * mz;
    d[u] = yy * inv - my * my;
    e[u] = yz * inv - my * mz;
    f[u] = zz * inv - mz * mz;
  }
};

// The covariances of a row's square windows of half-width radius from the
// row's column sums (the moments of the window's rows, per column, with
// radius zeros either side): window u sums columns u - radius .. u + radius
// directly, so no sum runs along the row and float keeps its precision.
// Radius is an int or, for the default, a compile-time constant
// (withDefault), whose terms unroll in one loop. A radius known only at run
// time adds term by term over the whole row into `boxes` instead, which
// vectorises whatever the radius; the sums are the same.
template <class Radius>
RISAS_VECTOR_CLONES
void boxCovariances(const RowMoments& columns, int cols, Radius radius, RowMoments& boxes, RowCovariances& out) {
  if constexpr (std::is_integral_v<Radius>) {
    for (int k = 0; k < kMoments; ++k) {
      const float* column = columns[k];
      float* sum = boxes[k];
      std::copy(column - radius, column - radius + cols, sum);
      for (int t = 1 - radius; t <= radius; ++t) {
        for (int u = 0; u < cols; ++u) sum[u] += column[u + t];
      }
    }
  }
  const auto box = [&](int k, int u) {
    if constexpr (std::is_integral_v<Radius>) {
      return static_cast<const RowMoments&>(boxes)[k][u];
    } else {
      const float* column = columns[k];
      float sum = column[u - radius];
      for (int t = 1 - radius; t <= radius; ++t) sum += column[u + t];
      return sum;
    }
  };
#pragma GCC ivdep  // the covariance's arrays are distinct
  for (int u = 0; u < cols; ++u) {
    out.set(u, box(kN, u), box(kX, u), box(kY, u), box(kZ, u), box(kXX, u), box(kXY, u), box(kXZ, u), box(kYY, u),
            box(kYZ, u), box(kZZ, u));
  }
}

// The window sums of points near a jump (sameSurfaceCovariance) read whole
// blocks of columns, up to kWindowLanes - 1 past a window's last.
constexpr int kWindowLanes = 4;

// m as a size x type view of an image kWindowLanes - 1 columns wider, zero
// there, so that reading whole blocks of columns stays inside it (the zeros
// are never used). Kept while it has the size and type.
void createPadded(cv::Mat& m, cv::Size size, int type) {
  const size_t padded_step = static_cast<size_t>(size.width + kWindowLanes - 1) * CV_ELEM_SIZE(type);
  if (m.size() == size && m.type() == type && m.step[0] >= padded_step) return;
  m = cv::Mat(size.height, size.width + kWindowLanes - 1, type, cv::Scalar::all(0)).colRange(0, size.width);
}

// A cloud of points as three planes of coordinates (padded, createPadded).
struct GridCloud {
  cv::Mat x, y, z;  // CV_32FC1, metres; NaN where there is no point
};

// The per-thread sums of one row of blocks (see gridPoints).
struct BlockRowSums {
  std::vector<float> first, count, sum_x, sum_y, sum_z;
};

// Row i of the grid (see gridPoints). Stride is an int or, for the default
// stride, a compile-time constant (withDefault): the loops over a block's
// columns then unroll, and the loops over blocks read the depth row a
// stride's columns at a time, which the compiler vectorises.
template <class Stride>
RISAS_VECTOR_CLONES
void gridRow(const cv::Mat& depth, const std::vector<float>& x_factor, const float* y_factor_of_row, int i,
             Stride stride, float depth_change_factor, BlockRowSums& sums, GridCloud& grid, cv::Mat& on_surface) {
  const int rows = depth.rows, cols = depth.cols, grid_cols = grid.z.cols;
  float *f = sums.first.data(), *n = sums.count.data();
  float *sx = sums.sum_x.data(), *sy = sums.sum_y.data(), *sz = sums.sum_z.data();
  const int r_begin = i * stride, r_end = std::min(r_begin + static_cast<int>(stride), rows);
  std::fill(sums.first.begin(), sums.first.end(), std::numeric_limits<float>::quiet_NaN());
  for (std::vector<float>* v : {&sums.count, &sums.sum_x, &sums.sum_y, &sums.sum_z}) {
    std::fill(v->begin(), v->end(), 0.0f);
  }
  // Blocks 0 .. whole - 1 have all stride columns, a partial block at the
  // right edge the `rest`.
  const int whole = cols / stride, rest = cols - whole * stride;
  // The first valid point, as the last one met going backwards: selecting on
  // the point just loaded, unlike selecting on whether one was found yet,
  // leaves the loop without branches, and it vectorises.
  for (int r = r_end - 1; r >= r_begin; --r) {
    const float* z = depth.ptr<float>(r);
    const auto visit = [&](int j, int columns) {
      float first = f[j];
      for (int k = columns - 1; k >= 0; --k) {
        const float candidate = z[j * stride + k];
        first = std::isnan(candidate) ? first : candidate;
      }
      f[j] = first;
    };
#pragma GCC ivdep  // the arrays are distinct
    for (int j = 0; j < whole; ++j) visit(j, stride);
    if (rest > 0) visit(whole, rest);
  }
  for (int r = r_begin; r < r_end; ++r) {
    const float* z = depth.ptr<float>(r);
    const float y = y_factor_of_row[r - r_begin];
    uchar* on = on_surface.ptr<uchar>(r);
    const float* x = x_factor.data();
    const auto visit = [&](int j, int columns) {
      // Added in the block's row-major order, as a running sum per block.
      float bn = n[j], bx = sx[j], by = sy[j], bz = sz[j];
      for (int k = 0; k < columns; ++k) {
        const int c = j * stride + k;
        // NaN compares false: a missing point is on no surface.
        const bool in = std::abs(z[c] - f[j]) <= depth_change_factor * f[j];
        const float zc = in ? z[c] : 0.0f;
        on[c] = in ? 255 : 0;
        bn += in ? 1.0f : 0.0f;
        bx += x[c] * zc;
        by += y * zc;
        bz += zc;
      }
      n[j] = bn, sx[j] = bx, sy[j] = by, sz[j] = bz;
    };
#pragma GCC ivdep  // the arrays are distinct
    for (int j = 0; j < whole; ++j) visit(j, stride);
    if (rest > 0) visit(whole, rest);
  }
  float *gx = grid.x.ptr<float>(i), *gy = grid.y.ptr<float>(i), *gz = grid.z.ptr<float>(i);
#pragma GCC ivdep  // the arrays are distinct
  for (int j = 0; j < grid_cols; ++j) {
    // A block without a point has the sums 0 and the count 0: 0 times
    // 1 / 0 makes its grid point NaN.
    const float inv = 1.0f / n[j];
    gx[j] = sx[j] * inv;
    gy[j] = sy[j] * inv;
    gz[j] = sz[j] * inv;
  }
}

// The grid the normals are fitted on: one point per stride x stride block
// (partial blocks at the right and bottom edges), the mean of the block's
// points on the same surface as its first valid one (in row-major order). All
// of those points weigh in, so the grid does not alias the depth noise.
// on_surface marks them: they are the pixels the block's normal belongs to.
// Computed from the depth and the back-projection factors, which give the
// very points backProject gives, and written as x, y and z planes, which the
// loops over blocks vectorise (an interleaved point does not load in one).
void gridPoints(const cv::Mat& depth, const std::vector<float>& x_factor, const std::vector<float>& y_factor,
                int stride, float depth_change_factor, GridCloud& grid, cv::Mat& on_surface) {
  const int rows = depth.rows, cols = depth.cols;
  const int grid_rows = (rows + stride - 1) / stride, grid_cols = (cols + stride - 1) / stride;
  for (cv::Mat* plane : {&grid.x, &grid.y, &grid.z}) createPadded(*plane, cv::Size(grid_cols, grid_rows), CV_32FC1);
  on_surface.create(depth.size(), CV_8UC1);
  cv::parallel_for_(cv::Range(0, grid_rows), [&](const cv::Range& range) {
    BlockRowSums& sums = Workspace::ofThisThread().get<BlockRowSums>();
    for (std::vector<float>* v : {&sums.first, &sums.count, &sums.sum_x, &sums.sum_y, &sums.sum_z}) {
      v->resize(static_cast<size_t>(grid_cols));
    }
    for (int i = range.start; i < range.end; ++i) {
      const float* y = y_factor.data() + i * stride;
      withDefault<GeometryParams::kDefaultNormalStride>(stride, [&](auto fixed_stride) {
        gridRow(depth, x_factor, y, i, fixed_stride, depth_change_factor, sums, grid, on_surface);
      });
    }
  });
}

// 0 at points with no depth or bordering a different surface (a depth jump to
// a 4-neighbour or a missing neighbour, which on Kinect-type sensors is the
// shadow of a jump), 255 elsewhere: the interiors of surfaces.
void surfaceInteriorMask(const cv::Mat& depth, float depth_change_factor, cv::Mat& mask) {
  mask.create(depth.size(), CV_8UC1);
  const int rows = depth.rows, cols = depth.cols;
  cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& range) {
    for (int r = range.start; r < range.end; ++r) {
      const float* z = depth.ptr<float>(r);
      const float* above = depth.ptr<float>(std::max(r - 1, 0));
      const float* below = depth.ptr<float>(std::min(r + 1, rows - 1));
      uchar* m = mask.ptr<uchar>(r);
      // Copied: the byte stores could alias anything read through a reference.
      const float factor = depth_change_factor;
      const int width = cols;
      // NaN compares false: a missing neighbour fails the test, as does a
      // missing centre. Outside the image counts as the centre itself.
      const auto same = [=](int c, float neighbour) { return std::abs(neighbour - z[c]) <= factor * z[c]; };
      const auto interior = [=](int c, float left, float right) {
        return same(c, above[c]) & same(c, below[c]) & same(c, left) & same(c, right);
      };
      m[0] = interior(0, z[0], z[std::min(1, width - 1)]) ? 255 : 0;
      for (int c = 1; c < width - 1; ++c) m[c] = interior(c, z[c - 1], z[c + 1]) ? 255 : 0;  // vectorised
      if (width > 1) m[width - 1] = interior(width - 1, z[width - 2], z[width - 1]) ? 255 : 0;
    }
  });
}

// The covariance of the window's points on the same surface as its centre:
// the O(window) path for points near a jump, where a plain box would mix
// surfaces. Taken about the centre (the covariance does not change), where
// the offsets are centimetres and float sums are exact enough. A window row
// goes kWindowLanes columns at a time, selected by label in lanes (the
// compiler did not vectorise the loop over a window's few columns itself),
// column c + k into lane k; the blocks read up to kWindowLanes - 1 columns
// past the window, which the images' padding (createPadded) keeps inside
// them.
void sameSurfaceCovariance(const GridCloud& grid, const cv::Mat& surfaces, int v, int u, int radius,
                           RowCovariances& out) {
  using cv::v_float32x4;
  using cv::v_int32x4;
  static_assert(kWindowLanes == v_float32x4::nlanes, "a block is one vector");
  const int label = surfaces.at<int>(v, u);
  const v_float32x4 cx = cv::v_setall_f32(grid.x.at<float>(v, u)), cy = cv::v_setall_f32(grid.y.at<float>(v, u)),
                    cz = cv::v_setall_f32(grid.z.at<float>(v, u)), one = cv::v_setall_f32(1.0f);
  const int c_begin = std::max(u - radius, 0), c_last = std::min(u + radius, surfaces.cols - 1);
  const v_int32x4 target = cv::v_setall_s32(label), last = cv::v_setall_s32(c_last), lanes(0, 1, 2, 3);
  v_float32x4 s[kMoments];
  for (v_float32x4& sum : s) sum = cv::v_setzero_f32();
  for (int r = std::max(v - radius, 0); r <= std::min(v + radius, surfaces.rows - 1); ++r) {
    const int* l = surfaces.ptr<int>(r);
    const float *px = grid.x.ptr<float>(r), *py = grid.y.ptr<float>(r), *pz = grid.z.ptr<float>(r);
    for (int c = c_begin; c <= c_last; c += kWindowLanes) {
      // Masked, not branched on; a point of another surface may be NaN.
      const v_float32x4 in =
          cv::v_reinterpret_as_f32((cv::v_load(l + c) == target) & (lanes + cv::v_setall_s32(c) <= last));
      const v_float32x4 dx = (cv::v_load(px + c) - cx) & in, dy = (cv::v_load(py + c) - cy) & in,
                        dz = (cv::v_load(pz + c) - cz) & in;
      s[kN] += one & in;
      s[kX] += dx, s[kY] += dy, s[kZ] += dz;
      s[kXX] += dx * dx, s[kXY] += dx * dy, s[kXZ] += dx * dz;
      s[kYY] += dy * dy, s[kYZ] += dy * dz, s[kZZ] += dz * dz;
    }
  }
  float m[kMoments];
  for (int moment = 0; moment < kMoments; ++moment) {
    float lane[kWindowLanes];
    cv::v_store(lane, s[moment]);
    m[moment] = (lane[0] + lane[1]) + (lane[2] + lane[3]);
  }
  out.set(u, m[kN], m[kX], m[kY], m[kZ], m[kXX], m[kXY], m[kXZ], m[kYY], m[kYZ], m[kZZ]);
}

// Unit normals of a row's windows facing the camera; (0, 0, 0) where there
// are fewer than min_points points, no centre label, or no plane.
//
// The normal is the eigenvector of the covariance C for its smallest
// eigenvalue l1. The adjugate adj(C) has the same eigenvectors with
// eigenvalues l2 l3 >= l1 l3 >= l1 l2, so the normal is adj(C)'s dominant
// one; for a surface patch (l1 << l2) adj(C) is nearly rank one and its
// largest column already points along the normal. Two power iterations
// sharpen it by (l1/l2)^2 each: no trigonometric eigen-solver per pixel.
// Branch-free, in float, over the row: C is scaled to unit trace first, so
// every product stays far from float's range limits.
RISAS_VECTOR_CLONES
void fitRow(RowCovariances& cov, const float* centre_x, const float* centre_y, const float* centre_z,
            const int* label, float min_points, int cols, cv::Vec3f* normals) {
  // adj(C) of a collinear window (l2 = 0) is zero up to rounding: it has
  // no plane. Its dominant eigenvalue l2 l3 must clear float's noise.
  constexpr float kMinPlaneness = 1e-6f;
  const float *cn = cov.n.data(), *ca = cov.a.data(), *cb = cov.b.data(), *cc = cov.c.data();
  const float *cd = cov.d.data(), *ce = cov.e.data(), *cf = cov.f.data();
  float *nx = cov.nx.data(), *ny = cov.ny.data(), *nz = cov.nz.data();
#pragma GCC ivdep  // the arrays are distinct (GCC ignores __restrict on local pointers)
  for (int u = 0; u < cols; ++u) {
    // Bitwise & and arithmetic on safe operands, selected afterwards: the
    // loop stays free of branches and vectorises.
    const float trace = ca[u] + cd[u] + cf[u];
    const bool fitted = (label[u] != 0) & (cn[u] >= min_points) & (trace > 0.0f);
    const float s = (fitted ? 1.0f : 0.0f) / (fitted ? trace : 1.0f);
    const float a = ca[u] * s, b = cb[u] * s, c = cc[u] * s;
    const float d = cd[u] * s, e = ce[u] * s, f = cf[u] * s;
    // adj(C) of the symmetric C = [a b c; b d e; c e f], itself symmetric
    const float A00 = d * f - e * e, A01 = c * e - b * f, A02 = b * e - c * d;
    const float A11 = a * f - c * c, A12 = b * c - a * e, A22 = a * d - b * b;
    const float l0 = A00 * A00 + A01 * A01 + A02 * A02;
    const float l1 = A01 * A01 + A11 * A11 + A12 * A12;
    const float l2 = A02 * A02 + A12 * A12 + A22 * A22;
    // The largest column (|column|^2 = (l2 l3)^2 for a plane), scaled to
    // unit length. (Two single selections: a nested one does not vectorise.)
    const bool second = l1 >= l2;
    const float l12 = second ? l1 : l2;
    float x = second ? A01 : A02, y = second ? A11 : A12, z = second ? A12 : A22;
    const bool first = l0 >= l12;
    const float largest = first ? l0 : l12;
    x = first ? A00 : x, y = first ? A01 : y, z = first ? A02 : z;
    const bool planar = fitted & (largest > kMinPlaneness * kMinPlaneness);
    const float unit = (planar ? 1.0f : 0.0f) / std::sqrt(planar ? largest : 1.0f);
    x *= unit, y *= unit, z *= unit;
    for (int i = 0; i < 2; ++i) {
      const float px = A00 * x + A01 * y + A02 * z;
      const float py = A01 * x + A11 * y + A12 * z;
      const float pz = A02 * x + A12 * y + A22 * z;
      x = px, y = py, z = pz;
    }
    const float length2 = x * x + y * y + z * z;
    const bool found = planar & (length2 > 0.0f);
    const float scale = (found ? 1.0f : 0.0f) / std::sqrt(found ? length2 : 1.0f);
    nx[u] = x * scale, ny[u] = y * scale, nz[u] = z * scale;
  }
  // Facing the camera. A centre without a point (NaN) has no fit: (0, 0, 0).
  for (int u = 0; u < cols; ++u) {
    const cv::Vec3f n(nx[u], ny[u], nz[u]);
    normals[u] = n.dot(cv::Vec3f(centre_x[u], centre_y[u], centre_z[u])) > 0.0f ? -n : n;
  }
}

// The images of one frame's normals, one set per thread and reused from frame
// to frame: allocated afresh, their page faults cost as much as the fits.
struct NormalBuffers {
  GridCloud grid;
  cv::Mat interior, surfaces, labels_low, labels_high, window_low, window_high;
};

NormalBuffers& buffers() { return Workspace::ofThisThread().get<NormalBuffers>(); }

// Per point, whether its window holds one surface only: the largest and the
// smallest non-zero label in the window agree. labels_low and labels_high
// are the labels as float (exact below 2^24) with the border's 0 replaced by
// a value that never wins the window's minimum and maximum respectively.
void windowsOnOneSurface(const cv::Mat& surfaces, int radius, NormalBuffers& b) {
  b.labels_low.create(surfaces.size(), CV_32FC1);
  b.labels_high.create(surfaces.size(), CV_32FC1);
  for (int v = 0; v < surfaces.rows; ++v) {
    const int* label = surfaces.ptr<int>(v);
    float* low = b.labels_low.ptr<float>(v);
    float* high = b.labels_high.ptr<float>(v);
    for (int u = 0; u < surfaces.cols; ++u) {
      high[u] = static_cast<float>(label[u]);
      low[u] = label[u] ? high[u] : std::numeric_limits<float>::max();
    }
  }
  const cv::Mat window = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * radius + 1, 2 * radius + 1));
  cv::erode(b.labels_low, b.window_low, window, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
  cv::dilate(b.labels_high, b.window_high, window, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
}

// The window's half-width on the grid for the default normal_radius and stride.
constexpr int kDefaultGridRadius =
    (GeometryParams::kDefaultNormalRadius + GeometryParams::kDefaultNormalStride - 1) /
    GeometryParams::kDefaultNormalStride;

// A point near a band's points: the mean of the points of its middle row.
cv::Vec3f bandReference(const GridCloud& grid, int v_begin, int v_end) {
  const int v = (v_begin + v_end) / 2;
  const float *x = grid.x.ptr<float>(v), *y = grid.y.ptr<float>(v), *z = grid.z.ptr<float>(v);
  double sx = 0, sy = 0, sz = 0;
  int n = 0;
  for (int u = 0; u < grid.z.cols; ++u) {
    if (std::isnan(z[u])) continue;
    sx += x[u], sy += y[u], sz += z[u];
    ++n;
  }
  return n ? cv::Vec3f(static_cast<float>(sx / n), static_cast<float>(sy / n), static_cast<float>(sz / n))
           : cv::Vec3f(0, 0, 0);
}

// The per-thread state of a band of rows (see fitNormals).
struct BandBuffers {
  RowMoments columns, boxes;
  RowCovariances covariances;
  std::vector<uchar> mixed;  // see mixedWindows; 8 bytes of room for forEachMarked
};

// 1 where a row's window holds points of its centre's surface and of
// another (see windowsOnOneSurface), else 0.
RISAS_VECTOR_CLONES
void mixedWindows(const int* label, const float* low, const float* high, int cols, uchar* __restrict mixed) {
  for (int u = 0; u < cols; ++u) mixed[u] = (label[u] != 0) & (low[u] != high[u]);
}

// Normals fitted at every point of a (grid) cloud, windows of half-width
// radius; (0, 0, 0) where none.
void fitNormals(const GridCloud& grid, int radius, float depth_change_factor, int min_points, cv::Mat& normals) {
  NormalBuffers& b = buffers();
  const cv::Mat& interior = b.interior;
  surfaceInteriorMask(grid.z, depth_change_factor, b.interior);
  // A window takes only the points of the centre's own surface: the
  // connected part of the interior it lies in. Border points themselves
  // (label 0) get no normal and count in no window.
  cv::Mat& surfaces = b.surfaces;
  createPadded(surfaces, interior.size(), CV_32S);
  cv::connectedComponents(interior, surfaces, 4, CV_32S);
  // It writes into the padded view, which has its size and type (were it
  // to allocate afresh, the window sums would read past its rows).
  CV_Assert(surfaces.step[0] >= (surfaces.cols + kWindowLanes - 1) * sizeof(int));
  // Where the window reaches no other surface, its own surface's points are
  // all its interior points: a box sum of the interior's moments, O(1).
  // Only windows across a jump (two labels) need the O(window) sum.
  windowsOnOneSurface(surfaces, radius, b);

  // The box sums slide down bands of rows: a band starts its column sums
  // afresh and then adds the row entering the window and removes the one
  // leaving it. The bands are fixed, not the threads' share, so the sums,
  // rounding and all, do not depend on the number of threads.
  constexpr int kBandRows = 16;
  const int rows = grid.z.rows, cols = grid.z.cols;
  normals.create(grid.z.size(), CV_32FC3);
  cv::parallel_for_(cv::Range(0, (rows + kBandRows - 1) / kBandRows), [&](const cv::Range& bands) {
    BandBuffers& band = Workspace::ofThisThread().get<BandBuffers>();
    band.covariances.resize(cols);
    band.boxes.reset(cols, 0);
    band.mixed.assign(static_cast<size_t>(cols) + 8, 0);
    for (int i = bands.start; i < bands.end; ++i) {
      const int v_begin = i * kBandRows, v_end = std::min(v_begin + kBandRows, rows);
      band.columns.reset(cols, radius);
      const cv::Vec3f reference = bandReference(grid, v_begin, v_end);
      const auto accumulate = [&](int r, float sign) {
        band.columns.accumulate(grid.x.ptr<float>(r), grid.y.ptr<float>(r), grid.z.ptr<float>(r),
                                interior.ptr<uchar>(r), sign, reference);
      };
      for (int r = std::max(v_begin - radius, 0); r <= std::min(v_begin + radius, rows - 1); ++r) accumulate(r, 1.0f);
      for (int v = v_begin; v < v_end; ++v) {
        if (v > v_begin) {
          if (v + radius < rows) accumulate(v + radius, 1.0f);
          if (v - radius - 1 >= 0) accumulate(v - radius - 1, -1.0f);
        }
        withDefault<kDefaultGridRadius>(radius, [&](auto fixed_radius) {
          boxCovariances(band.columns, cols, fixed_radius, band.boxes, band.covariances);
        });
        const int* label = surfaces.ptr<int>(v);
        mixedWindows(label, b.window_low.ptr<float>(v), b.window_high.ptr<float>(v), cols, band.mixed.data());
        forEachMarked(band.mixed.data(), 0, cols, [&](int u) {
          sameSurfaceCovariance(grid, surfaces, v, u, radius, band.covariances);
        });
        fitRow(band.covariances, grid.x.ptr<float>(v), grid.y.ptr<float>(v), grid.z.ptr<float>(v), label,
               static_cast<float>(min_points), cols, normals.ptr<cv::Vec3f>(v));
      }
    }
  });
}

}  // namespace

void normalFitKernel(const cv::Mat& depth_metres, const std::vector<float>& x_factor,
                     const std::vector<float>& y_factor, const GeometryParams& params, cv::Mat& normals,
                     cv::Mat& on_block_surface) {
  const int stride = params.normal_stride;
  // On the grid, a jump is measured over stride pixels and the window holds
  // the grid points within normal_radius pixels of the centre.
  const float factor = static_cast<float>(params.depth_change_factor);
  const int grid_radius = std::max(1, (params.normal_radius + stride - 1) / stride);
  NormalBuffers& b = buffers();
  gridPoints(depth_metres, x_factor, y_factor, stride, factor, b.grid, on_block_surface);
  fitNormals(b.grid, grid_radius, factor * stride, params.min_normal_points, normals);
}

}  // namespace risas

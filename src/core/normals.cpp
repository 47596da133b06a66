#include "risas/geometry.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace risas {
namespace {

// Zeroth, first and second moments of a set of points: all the covariance of a
// window needs, and additive, so a box sum is four look-ups in an integral image.
struct Moments {
  double n = 0, x = 0, y = 0, z = 0, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;

  void add(const cv::Vec3f& p) {
    const double px = p[0], py = p[1], pz = p[2];
    n += 1; x += px; y += py; z += pz;
    xx += px * px; xy += px * py; xz += px * pz; yy += py * py; yz += py * pz; zz += pz * pz;
  }
  Moments& operator+=(const Moments& o) {
    n += o.n; x += o.x; y += o.y; z += o.z;
    xx += o.xx; xy += o.xy; xz += o.xz; yy += o.yy; yz += o.yz; zz += o.zz;
    return *this;
  }
  Moments& operator-=(const Moments& o) {
    n -= o.n; x -= o.x; y -= o.y; z -= o.z;
    xx -= o.xx; xy -= o.xy; xz -= o.xz; yy -= o.yy; yz -= o.yz; zz -= o.zz;
    return *this;
  }
};

// The integral image of the moments. Its storage is one buffer per thread,
// reused from frame to frame: allocating and zeroing it per frame showed in
// the profile. Each call still fills it whole, so results never depend on an
// earlier frame, and a thread computes one frame at a time.
class MomentIntegral {
 public:
  // Sums the points where mask is non-zero.
  MomentIntegral(const cv::Mat& points, const cv::Mat& mask) : stride_(points.cols + 1), sums_(buffer()) {
    sums_.resize(static_cast<size_t>(points.rows + 1) * stride_);  // grows once, never shrinks
    std::fill(sums_.begin(), sums_.begin() + static_cast<std::ptrdiff_t>(stride_), Moments());  // row 0
    for (int v = 0; v < points.rows; ++v) {
      const cv::Vec3f* p = points.ptr<cv::Vec3f>(v);
      const uchar* m = mask.ptr<uchar>(v);
      const Moments* above = &at(v, 0);
      Moments* cell = &at(v + 1, 0);
      cell[0] = Moments();  // column 0
      Moments row;
      for (int u = 0; u < points.cols; ++u) {
        if (m[u]) row.add(p[u]);
        cell[u + 1] = above[u + 1];
        cell[u + 1] += row;
      }
    }
  }

  // Moments of the summed points in rows [r0, r1) and columns [c0, c1).
  Moments box(int r0, int c0, int r1, int c1) const {
    Moments m = at(r1, c1);
    m -= at(r0, c1);
    m -= at(r1, c0);
    m += at(r0, c0);
    return m;
  }

 private:
  static std::vector<Moments>& buffer() {
    thread_local std::vector<Moments> storage;
    return storage;
  }
  Moments& at(int r, int c) { return sums_[static_cast<size_t>(r) * stride_ + c]; }
  const Moments& at(int r, int c) const { return sums_[static_cast<size_t>(r) * stride_ + c]; }

  size_t stride_;
  std::vector<Moments>& sums_;
};

// The grid the normals are fitted on: one point per stride x stride block
// (partial blocks at the right and bottom edges), the mean of the block's
// points on the same surface as its first valid one. All of those points
// weigh in, so the grid does not alias the depth noise. on_surface marks them:
// they are the pixels the block's normal belongs to.
void gridPoints(const cv::Mat& points, int stride, float depth_change_factor, cv::Mat& grid, cv::Mat& on_surface) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  grid.create((points.rows + stride - 1) / stride, (points.cols + stride - 1) / stride, CV_32FC3);
  on_surface.create(points.size(), CV_8UC1);
  cv::parallel_for_(cv::Range(0, grid.rows), [&](const cv::Range& grid_rows) {
    for (int i = grid_rows.start; i < grid_rows.end; ++i) {
      cv::Vec3f* g = grid.ptr<cv::Vec3f>(i);
      const int r_end = std::min((i + 1) * stride, points.rows);
      for (int j = 0; j < grid.cols; ++j) {
        const int c_end = std::min((j + 1) * stride, points.cols);
        cv::Vec3f sum(0, 0, 0), first(nan, nan, nan);
        int count = 0;
        for (int r = i * stride; r < r_end; ++r) {
          const cv::Vec3f* p = points.ptr<cv::Vec3f>(r);
          uchar* on = on_surface.ptr<uchar>(r);
          for (int c = j * stride; c < c_end; ++c) {
            on[c] = 0;
            if (std::isnan(p[c][2])) continue;
            if (count == 0) first = p[c];
            if (std::abs(p[c][2] - first[2]) > depth_change_factor * first[2]) continue;
            on[c] = 255;
            sum += p[c];
            ++count;
          }
        }
        g[j] = count ? sum * (1.0f / count) : first;
      }
    }
  });
}

// 0 at points with no depth or bordering a different surface (a depth jump to
// a 4-neighbour or a missing neighbour, which on Kinect-type sensors is the
// shadow of a jump), 255 elsewhere: the interiors of surfaces.
void surfaceInteriorMask(const cv::Mat& points, float depth_change_factor, cv::Mat& mask) {
  mask.create(points.size(), CV_8UC1);
  const int rows = points.rows, cols = points.cols;
  cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& range) {
    for (int r = range.start; r < range.end; ++r) {
      const cv::Vec3f* p = points.ptr<cv::Vec3f>(r);
      const cv::Vec3f* above = points.ptr<cv::Vec3f>(std::max(r - 1, 0));
      const cv::Vec3f* below = points.ptr<cv::Vec3f>(std::min(r + 1, rows - 1));
      uchar* m = mask.ptr<uchar>(r);
      for (int c = 0; c < cols; ++c) {
        const float z = p[c][2];
        const float limit = depth_change_factor * z;
        // NaN compares false: a missing neighbour fails the test, as does a
        // missing centre. Outside the image counts as the centre itself.
        const auto same = [&](float zn) { return std::abs(zn - z) <= limit; };
        m[c] = same(above[c][2]) && same(below[c][2]) && same(p[std::max(c - 1, 0)][2]) &&
                       same(p[std::min(c + 1, cols - 1)][2])
                   ? 255
                   : 0;
      }
    }
  });
}

// Moments of the window's points on the same surface as its centre: the
// O(window) path for points near a jump, where a plain box would mix
// surfaces. Taken about the centre (the covariance does not change), where
// the offsets are centimetres and float sums are exact enough.
Moments sameSurfaceMoments(const cv::Mat& points, const cv::Mat& surfaces, int v, int u, int radius) {
  const int label = surfaces.at<int>(v, u);
  const cv::Vec3f centre = points.at<cv::Vec3f>(v, u);
  float n = 0, x = 0, y = 0, z = 0, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (int r = std::max(v - radius, 0); r <= std::min(v + radius, points.rows - 1); ++r) {
    const int* l = surfaces.ptr<int>(r);
    const cv::Vec3f* p = points.ptr<cv::Vec3f>(r);
    for (int c = std::max(u - radius, 0); c <= std::min(u + radius, points.cols - 1); ++c) {
      if (l[c] != label) continue;
      const float dx = p[c][0] - centre[0], dy = p[c][1] - centre[1], dz = p[c][2] - centre[2];
      n += 1; x += dx; y += dy; z += dz;
      xx += dx * dx; xy += dx * dy; xz += dx * dz; yy += dy * dy; yz += dy * dz; zz += dz * dz;
    }
  }
  Moments m;
  m.n = n; m.x = x; m.y = y; m.z = z;
  m.xx = xx; m.xy = xy; m.xz = xz; m.yy = yy; m.yz = yz; m.zz = zz;
  return m;
}

// Unit normal of the window's points facing the camera, or none.
//
// The normal is the eigenvector of the covariance C for its smallest
// eigenvalue l1. The adjugate adj(C) has the same eigenvectors with
// eigenvalues l2 l3 >= l1 l3 >= l1 l2, so the normal is adj(C)'s dominant
// one; for a surface patch (l1 << l2) adj(C) is nearly rank one and its
// largest column already points along the normal. Two power iterations
// sharpen it by (l1/l2)^2 each: no trigonometric eigen-solver per pixel.
// (Unnormalised in between: the entries are products of variances, far
// from double's range limits.)
bool fitNormal(const Moments& m, const cv::Vec3f& centre, cv::Vec3f& normal) {
  const double inv = 1.0 / m.n;
  const double mx = m.x * inv, my = m.y * inv, mz = m.z * inv;
  const double a = m.xx * inv - mx * mx, b = m.xy * inv - mx * my, c = m.xz * inv - mx * mz;
  const double d = m.yy * inv - my * my, e = m.yz * inv - my * mz, f = m.zz * inv - mz * mz;
  // adj(C) of the symmetric C = [a b c; b d e; c e f], itself symmetric
  const double A00 = d * f - e * e, A01 = c * e - b * f, A02 = b * e - c * d;
  const double A11 = a * f - c * c, A12 = b * c - a * e, A22 = a * d - b * b;
  const double l0 = A00 * A00 + A01 * A01 + A02 * A02;
  const double l1 = A01 * A01 + A11 * A11 + A12 * A12;
  const double l2 = A02 * A02 + A12 * A12 + A22 * A22;
  double x, y, z;
  if (l0 >= l1 && l0 >= l2) {
    x = A00, y = A01, z = A02;
  } else if (l1 >= l2) {
    x = A01, y = A11, z = A12;
  } else {
    x = A02, y = A12, z = A22;
  }
  for (int i = 0; i < 2; ++i) {
    const double nx = A00 * x + A01 * y + A02 * z;
    const double ny = A01 * x + A11 * y + A12 * z;
    const double nz = A02 * x + A12 * y + A22 * z;
    x = nx, y = ny, z = nz;
  }
  const double length = std::sqrt(x * x + y * y + z * z);
  if (!(length > 0.0) || !std::isfinite(length)) return false;  // collinear or single points
  double scale = 1.0 / length;
  if (x * centre[0] + y * centre[1] + z * centre[2] > 0.0) scale = -scale;
  normal = cv::Vec3f(static_cast<float>(x * scale), static_cast<float>(y * scale), static_cast<float>(z * scale));
  return true;
}

// The images of one frame's normals, one set per thread and reused from frame
// to frame: allocated afresh, their page faults cost as much as the fits.
struct NormalBuffers {
  cv::Mat grid_points, interior, surfaces, labels_low, labels_high, window_low, window_high;
};

NormalBuffers& buffers() {
  thread_local NormalBuffers b;
  return b;
}

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

// Normals fitted at every point of a (grid) cloud, windows of half-width
// radius; (0, 0, 0) where none.
void fitNormals(const cv::Mat& points, int radius, float depth_change_factor, int min_points, cv::Mat& normals) {
  NormalBuffers& b = buffers();
  const cv::Mat& interior = b.interior;
  surfaceInteriorMask(points, depth_change_factor, b.interior);
  // A window takes only the points of the centre's own surface: the
  // connected part of the interior it lies in. Border points themselves
  // (label 0) get no normal and count in no window.
  cv::Mat& surfaces = b.surfaces;
  cv::connectedComponents(interior, surfaces, 4, CV_32S);
  // Where the window reaches no other surface, its own surface's points are
  // all its interior points: a box sum of the interior's moments, O(1).
  // Only windows across a jump (two labels) need the O(window) sum.
  const MomentIntegral integral(points, interior);
  windowsOnOneSurface(surfaces, radius, b);

  normals.create(points.size(), CV_32FC3);
  cv::parallel_for_(cv::Range(0, points.rows), [&](const cv::Range& range) {
    for (int v = range.start; v < range.end; ++v) {
      const int* label = surfaces.ptr<int>(v);
      const float* low = b.window_low.ptr<float>(v);
      const float* high = b.window_high.ptr<float>(v);
      const cv::Vec3f* p = points.ptr<cv::Vec3f>(v);
      cv::Vec3f* n = normals.ptr<cv::Vec3f>(v);
      for (int u = 0; u < points.cols; ++u) {
        n[u] = cv::Vec3f(0, 0, 0);
        if (label[u] == 0) continue;
        const Moments m = low[u] == high[u] ? integral.box(std::max(v - radius, 0), std::max(u - radius, 0),
                                                           std::min(v + radius + 1, points.rows),
                                                           std::min(u + radius + 1, points.cols))
                                            : sameSurfaceMoments(points, surfaces, v, u, radius);
        if (m.n >= min_points) fitNormal(m, p[u], n[u]);
      }
    }
  });
}

}  // namespace

void estimateNormals(const cv::Mat& points, const GeometryParams& params, cv::Mat& normals, cv::Mat& on_block_surface) {
  CV_Assert(points.type() == CV_32FC3);
  const int stride = params.normal_stride;
  // On the grid, a jump is measured over stride pixels and the window holds
  // the grid points within normal_radius pixels of the centre.
  const float factor = static_cast<float>(params.depth_change_factor);
  const int grid_radius = std::max(1, (params.normal_radius + stride - 1) / stride);
  NormalBuffers& b = buffers();
  gridPoints(points, stride, factor, b.grid_points, on_block_surface);
  fitNormals(b.grid_points, grid_radius, factor * stride, params.min_normal_points, normals);
}

}  // namespace risas

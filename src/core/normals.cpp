#include "risas/geometry.hpp"

#include <Eigen/Core>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
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

// The integral image of the moments. Its storage (about 25 MB at VGA) is one
// buffer per thread, reused from frame to frame: allocating and zeroing it
// per frame showed in the profile. Each call still fills it whole, so results
// never depend on an earlier frame, and a thread computes one frame at a time.
class MomentIntegral {
 public:
  explicit MomentIntegral(const cv::Mat& points) : stride_(points.cols + 1), sums_(buffer()) {
    sums_.resize(static_cast<size_t>(points.rows + 1) * stride_);  // grows once, never shrinks
    std::fill(sums_.begin(), sums_.begin() + static_cast<std::ptrdiff_t>(stride_), Moments());  // row 0
    for (int v = 0; v < points.rows; ++v) {
      const cv::Vec3f* p = points.ptr<cv::Vec3f>(v);
      at(v + 1, 0) = Moments();  // column 0
      Moments row;
      for (int u = 0; u < points.cols; ++u) {
        if (!std::isnan(p[u][2])) row.add(p[u]);
        Moments& cell = at(v + 1, u + 1);
        cell = at(v, u + 1);
        cell += row;
      }
    }
  }

  // Moments of the valid points in rows [r0, r1) and columns [c0, c1).
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

// 0 at pixels with no depth or bordering a different surface (a depth jump to
// a 4-neighbour or a missing neighbour, which on Kinect-type sensors is the
// shadow of a jump), 255 elsewhere: the interiors of surfaces.
cv::Mat surfaceInteriorMask(const cv::Mat& points, double depth_change_factor) {
  cv::Mat mask(points.size(), CV_8UC1, cv::Scalar(0));
  const auto depth = [&](int r, int c) { return points.at<cv::Vec3f>(r, c)[2]; };
  for (int r = 0; r < points.rows; ++r) {
    for (int c = 0; c < points.cols; ++c) {
      const float z = depth(r, c);
      if (std::isnan(z)) continue;
      const float limit = static_cast<float>(depth_change_factor) * z;
      const auto jumps = [&](int rn, int cn) {
        if (rn < 0 || cn < 0 || rn >= points.rows || cn >= points.cols) return false;
        const float zn = depth(rn, cn);
        return std::isnan(zn) || std::abs(zn - z) > limit;
      };
      if (!(jumps(r - 1, c) || jumps(r + 1, c) || jumps(r, c - 1) || jumps(r, c + 1))) mask.at<uchar>(r, c) = 255;
    }
  }
  return mask;
}

// Moments of the window's points on the same surface as its centre: the
// O(window) path for pixels near a jump, where a plain box would mix surfaces.
Moments sameSurfaceMoments(const cv::Mat& points, const cv::Mat& surfaces, int v, int u, int radius) {
  Moments m;
  const int label = surfaces.at<int>(v, u);
  for (int r = std::max(v - radius, 0); r <= std::min(v + radius, points.rows - 1); ++r) {
    const int* l = surfaces.ptr<int>(r);
    const cv::Vec3f* p = points.ptr<cv::Vec3f>(r);
    for (int c = std::max(u - radius, 0); c <= std::min(u + radius, points.cols - 1); ++c) {
      if (l[c] == label) m.add(p[c]);
    }
  }
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
bool fitNormal(const Moments& m, const cv::Vec3f& centre, cv::Vec3f& normal) {
  const double inv = 1.0 / m.n;
  const double mx = m.x * inv, my = m.y * inv, mz = m.z * inv;
  const double a = m.xx * inv - mx * mx, b = m.xy * inv - mx * my, c = m.xz * inv - mx * mz;
  const double d = m.yy * inv - my * my, e = m.yz * inv - my * mz, f = m.zz * inv - mz * mz;
  // adj(C) of the symmetric C = [a b c; b d e; c e f]
  const Eigen::Matrix3d adj = (Eigen::Matrix3d() << d * f - e * e, c * e - b * f, b * e - c * d,  //
                               c * e - b * f, a * f - c * c, b * c - a * e,                        //
                               b * e - c * d, b * c - a * e, a * d - b * b)
                                  .finished();
  Eigen::Index column = 0;
  adj.colwise().squaredNorm().maxCoeff(&column);
  Eigen::Vector3d n = adj.col(column);
  for (int i = 0; i < 2; ++i) {
    const double length = n.norm();
    if (!(length > 0.0) || !std::isfinite(length)) return false;  // collinear or single points
    n = adj * (n / length);
  }
  const double length = n.norm();
  if (!(length > 0.0) || !std::isfinite(length)) return false;
  n /= length;
  if (n.dot(Eigen::Vector3d(centre[0], centre[1], centre[2])) > 0.0) n = -n;
  normal = cv::Vec3f(static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z()));
  return true;
}

}  // namespace

cv::Mat estimateNormals(const cv::Mat& points, const GeometryParams& params) {
  CV_Assert(points.type() == CV_32FC3);
  const MomentIntegral integral(points);
  const cv::Mat interior = surfaceInteriorMask(points, params.depth_change_factor);
  // Chessboard distance to the nearest surface border: a window of that
  // half-width holds one surface only, and its box sum is O(1).
  cv::Mat distance, surfaces;
  cv::distanceTransform(interior, distance, cv::DIST_C, 3);
  // Closer to a border, the window keeps its size but takes only the points of
  // the centre's own surface: the connected part of the interior it lies in.
  // Border pixels themselves (label 0) get no normal.
  cv::connectedComponents(interior, surfaces, 4, CV_32S);

  const int R = params.normal_radius;
  const int stride = params.normal_stride;
  const auto fitAt = [&](int v, int u, cv::Vec3f& normal) {
    const Moments m = distance.at<float>(v, u) > R
                          ? integral.box(std::max(v - R, 0), std::max(u - R, 0), std::min(v + R + 1, points.rows),
                                         std::min(u + R + 1, points.cols))
                          : sameSurfaceMoments(points, surfaces, v, u, R);
    return m.n >= params.min_normal_points && fitNormal(m, points.at<cv::Vec3f>(v, u), normal);
  };
  // Fits on a grid of every stride-th pixel...
  const int grid_rows = (points.rows - 1) / stride + 1, grid_cols = (points.cols - 1) / stride + 1;
  cv::Mat grid(grid_rows, grid_cols, CV_32FC3, cv::Scalar::all(0));
  cv::parallel_for_(cv::Range(0, grid_rows), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      for (int j = 0; j < grid_cols; ++j) {
        if (surfaces.at<int>(i * stride, j * stride) != 0) fitAt(i * stride, j * stride, grid.at<cv::Vec3f>(i, j));
      }
    }
  });
  // ...and each pixel interpolates bilinearly between the grid fits around it
  // that lie on its own surface, so normals vary smoothly with position (a
  // nearest-fit copy would shift them in a pattern fixed to the pixel grid).
  // A pixel with no such fit around it gets its own.
  cv::Mat normals(points.size(), CV_32FC3, cv::Scalar::all(0));
  cv::parallel_for_(cv::Range(0, points.rows), [&](const cv::Range& range) {
    for (int v = range.start; v < range.end; ++v) {
      const int i = v / stride;
      const float fv = static_cast<float>(v - i * stride) / stride;
      const int* label = surfaces.ptr<int>(v);
      cv::Vec3f* n = normals.ptr<cv::Vec3f>(v);
      for (int u = 0; u < points.cols; ++u) {
        if (label[u] == 0) continue;  // a surface border: no normal
        const int j = u / stride;
        const float fu = static_cast<float>(u - j * stride) / stride;
        cv::Vec3f sum(0, 0, 0);
        for (int di = 0; di <= 1; ++di) {
          for (int dj = 0; dj <= 1; ++dj) {
            const float w = (di ? fv : 1.0f - fv) * (dj ? fu : 1.0f - fu);
            const int gi = i + di, gj = j + dj;
            if (w == 0.0f || gi >= grid_rows || gj >= grid_cols) continue;
            const cv::Vec3f& g = grid.at<cv::Vec3f>(gi, gj);
            if (g[2] != 0.0f && surfaces.at<int>(gi * stride, gj * stride) == label[u]) sum += w * g;
          }
        }
        const float length = static_cast<float>(cv::norm(sum));
        if (length > 1e-3f) {
          n[u] = sum / length;
        } else {
          fitAt(v, u, n[u]);
        }
      }
    }
  });
  return normals;
}

}  // namespace risas

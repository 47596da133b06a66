// The fast kernel of the descriptor's histogram (PatchEncoder::encode,
// encoding.cpp): the same samples, labels and histogram, each pass over the
// disc's samples one loop over arrays that vectorises. See
// patch_encoding.hpp for the contract.
#include "patch_encoding.hpp"

#include "risas/ranking.hpp"
#include "risas/workspace.hpp"

#include "vector_clones.hpp"
#include "with_default.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace risas {

namespace {

// One pyramid level's reads for each sample (greyAt): the bilinear cell's
// corner in the level, the point's place in the cell, the cell's grey
// values, bytes 0 to 3: (u0, v0), (u0 + 1, v0), (u0, v0 + 1) and
// (u0 + 1, v0 + 1), and the bilinear value.
struct LevelReads {
  std::vector<int> u0, v0;
  std::vector<float> a, b, grey;
  std::vector<uint32_t> cell;
  void resize(size_t n) {
    for (auto* v : {&u0, &v0}) v->resize(n);
    for (auto* v : {&a, &b, &grey}) v->resize(n);
    cell.resize(n);
  }
};

// One keypoint's samples, an array per quantity, so that the loops over the
// samples vectorise. One set per thread, reused from keypoint to keypoint.
struct DiscSamples {
  std::vector<float> x, y;  // image position
  std::vector<int> u, v;    // nearest pixel
  std::vector<uint8_t> inside, on_surface;
  LevelReads finer, coarser;  // the two pyramid levels read; finer.grey ends as the blend
  std::vector<float> z, x_factor, y_factor, nx, ny, nz;  // at the nearest pixel
  std::vector<uint8_t> counts, level;
  std::vector<uint16_t> rho_level;
  void resize(size_t n) {
    for (auto* a : {&x, &y, &z, &x_factor, &y_factor, &nx, &ny, &nz}) a->resize(n);
    for (auto* a : {&u, &v}) a->resize(n);
    for (auto* a : {&inside, &on_surface, &counts, &level}) a->resize(n);
    finer.resize(n);
    coarser.resize(n);
    rho_level.resize(n);
  }
};

DiscSamples& discSamples() { return Workspace::ofThisThread().get<DiscSamples>(); }

// The histogram of one patch (PatchEncoder::encode): counts, or soft
// binning's weighted votes.
struct Histogram {
  std::vector<int> counts;
  std::vector<float> votes;
};

// The disc's offsets (di, dj) in units of its radius, rotated by theta
// (cos_t and sin_t scaled by the radius) about the keypoint (cu, cv): the
// patch's x axis along theta, its y axis 90 degrees on (image v points
// down). Each sample's nearest pixel (rounded half to even, as cvRound),
// clamped into the image; samples outside it are marked.
RISAS_VECTOR_CLONES
void placeSamples(const float* di, const float* dj, int n, float cu, float cv, float cos_t, float sin_t, int cols,
                  int rows, DiscSamples& d) {
  const float max_u = static_cast<float>(cols - 1), max_v = static_cast<float>(rows - 1);
  float *x = d.x.data(), *y = d.y.data();
  int *u = d.u.data(), *v = d.v.data();
  uint8_t* inside = d.inside.data();
#pragma GCC ivdep  // the arrays are distinct
  for (int s = 0; s < n; ++s) {
    const float xs = cu + cos_t * di[s] - sin_t * dj[s];
    const float ys = cv + sin_t * di[s] + cos_t * dj[s];
    x[s] = xs, y[s] = ys;
    inside[s] = (xs >= 0.0f) & (ys >= 0.0f) & (xs <= max_u) & (ys <= max_v);
    // Clamped in float first, so that the conversions stay in an int's range.
    const float xc = std::min(xs > 0.0f ? xs : 0.0f, max_u), yc = std::min(ys > 0.0f ? ys : 0.0f, max_v);
    u[s] = static_cast<int>(std::nearbyint(xc));
    v[s] = static_cast<int>(std::nearbyint(yc));
  }
}

// Each sample's bilinear cell in a pyramid level of cols x rows pixels:
// its position times `scale` (the level's 2^-l), clamped into the level,
// as greyAt's bilinear.
RISAS_VECTOR_CLONES
void placeOnLevel(const float* x, const float* y, int n, float scale, int cols, int rows, LevelReads& r) {
  const float max_u = static_cast<float>(cols - 1), max_v = static_cast<float>(rows - 1);
  int *u0 = r.u0.data(), *v0 = r.v0.data();
  float *a = r.a.data(), *b = r.b.data();
#pragma GCC ivdep  // the arrays are distinct
  for (int s = 0; s < n; ++s) {
    const float xs = x[s] * scale, ys = y[s] * scale;
    const float xc = std::min(xs > 0.0f ? xs : 0.0f, max_u), yc = std::min(ys > 0.0f ? ys : 0.0f, max_v);
    u0[s] = std::min(static_cast<int>(xc), cols - 2);
    v0[s] = std::min(static_cast<int>(yc), rows - 2);
    a[s] = xc - static_cast<float>(u0[s]);
    b[s] = yc - static_cast<float>(v0[s]);
  }
}

// Each sample's cell's 2 x 2 grey values in `level`, one by one.
void lookUpCells(const cv::Mat& level, int n, LevelReads& r) {
  const int *pu0 = r.u0.data(), *pv0 = r.v0.data();
  uint32_t* cell = r.cell.data();
  const uchar* data = level.data;
  const size_t step = level.step;
  for (int s = 0; s < n; ++s) {
    // The four in one store (and, on a little-endian CPU, each row's two in
    // one load: the compiler merges them).
    const uchar* row0 = data + static_cast<size_t>(pv0[s]) * step + pu0[s];
    const uchar* row1 = row0 + step;
    cell[s] = static_cast<uint32_t>(row0[0]) | static_cast<uint32_t>(row0[1]) << 8 |
              static_cast<uint32_t>(row1[0]) << 16 | static_cast<uint32_t>(row1[1]) << 24;
  }
}

// The bilinear value of each sample's cell.
RISAS_VECTOR_CLONES
void interpolateCells(int n, LevelReads& r) {
  const float *a = r.a.data(), *b = r.b.data();
  const uint32_t* cell = r.cell.data();
  float* grey = r.grey.data();
#pragma GCC ivdep  // the arrays are distinct
  for (int s = 0; s < n; ++s) {
    const float g00 = static_cast<float>(cell[s] & 0xff), g01 = static_cast<float>(cell[s] >> 8 & 0xff);
    const float g10 = static_cast<float>(cell[s] >> 16 & 0xff), g11 = static_cast<float>(cell[s] >> 24);
    grey[s] = (1.0f - b[s]) * ((1.0f - a[s]) * g00 + a[s] * g01) + b[s] * ((1.0f - a[s]) * g10 + a[s] * g11);
  }
}

// finer.grey = (1 - f) finer.grey + f coarser.grey, greyAt's blend.
RISAS_VECTOR_CLONES
void blendLevels(int n, float f, DiscSamples& d) {
  float* finer = d.finer.grey.data();
  const float* coarser = d.coarser.grey.data();
#pragma GCC ivdep  // the arrays are distinct
  for (int s = 0; s < n; ++s) finer[s] = (1.0f - f) * finer[s] + f * coarser[s];
}

// Each sample's grey value at fractional level lambda (greyAt), into
// d.finer.grey.
void readGrey(const GreyPyramid& grey, float lambda, int n, DiscSamples& d) {
  const int l = static_cast<int>(lambda);
  const float f = lambda - static_cast<float>(l);
  const auto read = [&](int level, LevelReads& r) {
    const cv::Mat& image = grey.level[level];
    placeOnLevel(d.x.data(), d.y.data(), n, std::ldexp(1.0f, -level), image.cols, image.rows, r);
    lookUpCells(image, n, r);
    interpolateCells(n, r);
  };
  read(l, d.finer);
  if (f == 0.0f) return;
  read(l + 1, d.coarser);
  blendLevels(n, f, d);
}

// Each sample's look-ups, one by one: its pixel's surface flag, block normal,
// depth and back-projection factors. In two passes, the normals in the
// second: in one, the loop held more pointers than the CPU has registers and
// reloaded them every sample. Stride is an int or, for the default, a
// compile-time constant (a shift).
template <class Stride>
void lookUpSamples(const FrameGeometry& geometry, Stride stride, int n, DiscSamples& d) {
  // Raw pointers and steps, read once: the byte stores could alias
  // anything read through d, geometry or the images' headers.
  const int *pu = d.u.data(), *pv = d.v.data();
  uint8_t* on = d.on_surface.data();
  float *z = d.z.data(), *x_factor = d.x_factor.data(), *y_factor = d.y_factor.data();
  const uchar* on_data = geometry.on_block_surface.data;
  const size_t on_step = geometry.on_block_surface.step;
  const uchar* depth_data = geometry.depth.data;
  const size_t depth_step = geometry.depth.step;
  const float *x_table = geometry.x_factor.data(), *y_table = geometry.y_factor.data();
  for (int s = 0; s < n; ++s) {
    const unsigned u = static_cast<unsigned>(pu[s]), v = static_cast<unsigned>(pv[s]);
    on[s] = on_data[v * on_step + u];
    z[s] = reinterpret_cast<const float*>(depth_data + v * depth_step)[u];
    x_factor[s] = x_table[u];
    y_factor[s] = y_table[v];
  }
  float *nx = d.nx.data(), *ny = d.ny.data(), *nz = d.nz.data();
  const uchar* normals_data = geometry.normals.data;
  const size_t normals_step = geometry.normals.step;
  const unsigned block_stride = stride;  // a shift for the default stride
  for (int s = 0; s < n; ++s) {
    const unsigned u = static_cast<unsigned>(pu[s]), v = static_cast<unsigned>(pv[s]);
    const float* normal =
        reinterpret_cast<const float*>(normals_data + v / block_stride * normals_step) + u / block_stride * 3;
    nx[s] = normal[0], ny[s] = normal[1], nz[s] = normal[2];
  }
}

// The keypoint's point k and normal n_k, with the squared background
// distance t^2 and rho-bar.
struct KeypointFrame {
  float kx, ky, kz, nkx, nky, nkz, t2, rho_bar;
};

// Which samples count (inside the image, on their block's surface with a
// normal, FrameGeometry::hasNormal, and not background, eq. 5), their
// grey value (readGrey) rounded to 0 .. 255, and their shape level: the flat
// majority (rho >= rho-bar) is level kRhoLevels, the rest are ranked on
// kRhoLevels levels of rho / rho-bar.
constexpr int kRhoLevels = 256;
RISAS_VECTOR_CLONES
void labelSamples(const KeypointFrame& k, int n, DiscSamples& d) {
  const KeypointFrame f = k;  // copied, and raw pointers: the byte stores could alias anything read through d
  const float *z = d.z.data(), *x_factor = d.x_factor.data();
  const float *y_factor = d.y_factor.data(), *nx = d.nx.data(), *ny = d.ny.data(), *nz = d.nz.data();
  const float* grey = d.finer.grey.data();
  const uint8_t *inside = d.inside.data(), *on = d.on_surface.data();
  uint8_t *counts = d.counts.data(), *level = d.level.data();
  uint16_t* rho_level = d.rho_level.data();
#pragma GCC ivdep  // the arrays are distinct
  for (int s = 0; s < n; ++s) {
    const float dx = x_factor[s] * z[s] - f.kx, dy = y_factor[s] * z[s] - f.ky, dz = z[s] - f.kz;
    counts[s] = inside[s] & (on[s] != 0) & (nz[s] != 0.0f) & (dx * dx + dy * dy + dz * dz < f.t2);
    // Rounded; in [0, 255] (every level is clamped into its image).
    level[s] = static_cast<uint8_t>(static_cast<int>(grey[s] + 0.5f));
    const float rho = std::abs(f.nkx * nx[s] + f.nky * ny[s] + f.nkz * nz[s]);
    const float ratio = rho < f.rho_bar ? rho / f.rho_bar : 1.0f;  // no division by a rho-bar of 0
    const int ranked = std::min(static_cast<int>(ratio * kRhoLevels), kRhoLevels - 1);
    rho_level[s] = static_cast<uint16_t>(rho >= f.rho_bar ? kRhoLevels : ranked);
  }
}

// bins[0] += a, bins[1] += b, as one two-float addition where the compiler
// has vectors.
inline void addPair(float* bins, float a, float b) {
  typedef float Pair __attribute__((vector_size(8)));
  Pair pair;
  std::memcpy(&pair, bins, sizeof pair);
  pair += Pair{a, b};
  std::memcpy(bins, &pair, sizeof pair);
}

// The paper's histogram: each counted sample one vote in its (sector, rank
// group, shape label) bin, added without a branch (a sample adds its count,
// 0 or 1). Into out, dimension floats, not normalised.
void countHistogram(const DiscSamples& d, int n, const std::vector<uint16_t>& sector, const int* intensity_count,
                    const uint8_t* shape_label, int n_bin, int n_shape, int dimension, float* out) {
  uint8_t intensity_label[256];  // each level's group, tabulated once (counting sort)
  rankGroupTable(intensity_count, 256, n_bin, intensity_label);
  std::vector<int>& histogram = Workspace::ofThisThread().get<Histogram>().counts;
  histogram.assign(static_cast<size_t>(dimension), 0);
  for (int s = 0; s < n; ++s) {
    const int bin = (sector[static_cast<size_t>(s)] * n_bin + intensity_label[d.level[s]]) * n_shape +
                    shape_label[d.rho_level[s]];
    histogram[static_cast<size_t>(bin)] += d.counts[s];
  }
  for (int i = 0; i < dimension; ++i) out[i] = static_cast<float>(histogram[static_cast<size_t>(i)]);
}

// soft_binning's histogram: the readable encoding's two votes per counted
// sample, between the rank groups rankPositionTable gives its grey level
// under the grey image's noise.
// Here the bins are laid out [sector][shape][group] (one spare bin at the
// end), so that a sample's two groups are neighbours and take one two-float
// addition. In the last group the upper weight is 0 and its addition, into
// the next shape's first bin or the spare one, changes nothing. Reordered
// into the readable layout in out, dimension floats, not normalised.
void softHistogram(const DiscSamples& d, int n, const std::vector<uint16_t>& sector, const int* intensity_count,
                   float grey_noise, const uint8_t* shape_label, int n_bin, int n_shape, int dimension, float* out) {
  uint8_t lower_group[256];
  float upper_group_weight[256];
  rankPositionTable(intensity_count, 256, n_bin, grey_noise, lower_group, upper_group_weight);
  const int sector_step = n_shape * n_bin, sectors = dimension / sector_step;
  std::vector<float>& votes = Workspace::ofThisThread().get<Histogram>().votes;
  votes.assign(static_cast<size_t>(dimension) + 1, 0.0f);
  for (int s = 0; s < n; ++s) {
    if (!d.counts[s]) continue;
    const int level = d.level[s];
    const float wg = upper_group_weight[level];
    const int bin =
        sector[static_cast<size_t>(s)] * sector_step + shape_label[d.rho_level[s]] * n_bin + lower_group[level];
    addPair(votes.data() + bin, 1.0f - wg, wg);
  }
  for (int sec = 0; sec < sectors; ++sec) {
    for (int group = 0; group < n_bin; ++group) {
      for (int shape = 0; shape < n_shape; ++shape) {
        out[(sec * n_bin + group) * n_shape + shape] =
            votes[static_cast<size_t>(sec * sector_step + shape * n_bin + group)];
      }
    }
  }
}

// The shape labels' own histogram (DescriptorParams::shape_weight): each
// counted sample one vote in its (sector, shape label) bin. Into out, bins
// floats, not normalised.
void shapeHistogram(const DiscSamples& d, int n, const std::vector<uint16_t>& sector, const uint8_t* shape_label,
                    int n_shape, float* out, int bins) {
  std::fill(out, out + bins, 0.0f);
  for (int s = 0; s < n; ++s) {
    out[sector[static_cast<size_t>(s)] * n_shape + shape_label[d.rho_level[s]]] += static_cast<float>(d.counts[s]);
  }
}

// values[0 .. count) scaled to L2 length `length`.
void scaleToLength(float* values, int count, float length) {
  float norm = 0.0f;
  for (int i = 0; i < count; ++i) norm += values[i] * values[i];
  const float scale = length / std::sqrt(norm);
  for (int i = 0; i < count; ++i) values[i] *= scale;
}

}  // namespace

bool encodePatchKernel(const GreyPyramid& grey, float lambda, const FrameGeometry& geometry, const Neighbourhood& nb,
                       float radius_px, double theta, const DiscLayout& disc, const DescriptorParams& params,
                       float* out) {
  const cv::Mat& gray = grey.level[0];
  const int n = static_cast<int>(disc.i.size());
  const int dimension = params.dimension();
  DiscSamples& d = discSamples();
  d.resize(static_cast<size_t>(n));
  placeSamples(disc.i.data(), disc.j.data(), n, nb.centre.x, nb.centre.y,
               static_cast<float>(std::cos(theta)) * radius_px, static_cast<float>(std::sin(theta)) * radius_px,
               gray.cols, gray.rows, d);
  withDefault<GeometryParams::kDefaultNormalStride>(geometry.normal_stride, [&](auto stride) {
    lookUpSamples(geometry, stride, n, d);
  });
  readGrey(grey, lambda, n, d);
  const KeypointFrame k{static_cast<float>(nb.point.x()),  static_cast<float>(nb.point.y()),
                        static_cast<float>(nb.point.z()),  static_cast<float>(nb.normal.x()),
                        static_cast<float>(nb.normal.y()), static_cast<float>(nb.normal.z()),
                        static_cast<float>(params.background_distance * params.background_distance),
                        static_cast<float>(params.rho_threshold)};
  labelSamples(k, n, d);

  // The level histograms of the counted samples, added to without a branch
  // (a sample adds its count, 0 or 1). rho_count[kRhoLevels] counts the
  // flat samples, which are not ranked.
  int intensity_count[256] = {}, rho_count[kRhoLevels + 1] = {}, counted = 0;
  for (int s = 0; s < n; ++s) {
    intensity_count[d.level[s]] += d.counts[s];
    rho_count[d.rho_level[s]] += d.counts[s];
    counted += d.counts[s];
  }
  if (counted < params.min_valid_fraction * n || counted < 3) return false;

  // Rank groups by counting sort: a sample's group depends only on its
  // level, so each level's group is tabulated once (the grey levels' in the
  // histogram functions).
  // With n_vec 0 there are no shape labels: every sample label 0.
  uint8_t shape_label[kRhoLevels + 1] = {};
  if (params.n_vec > 0) rankGroupTable(rho_count, kRhoLevels, params.n_vec, shape_label);
  shape_label[kRhoLevels] = static_cast<uint8_t>(params.n_vec);

  // With a shape histogram of its own (shape_weight) the intensity
  // histogram's samples all take shape label 0, and the shape histogram
  // follows it.
  const bool own_shape = params.ownShapeHistogram();
  const int n_shape = params.n_vec + 1, joint_shapes = own_shape ? 1 : n_shape;
  const int intensity_bins = own_shape ? dimension - params.n_ring * params.n_pie * n_shape : dimension;
  static constexpr uint8_t kNoLabel[kRhoLevels + 1] = {};
  const uint8_t* joint_label = own_shape ? kNoLabel : shape_label;
  if (params.soft_binning) {
    softHistogram(d, n, disc.sector, intensity_count, grey.noise, joint_label, params.n_bin, joint_shapes,
                  intensity_bins, out);
  } else {
    countHistogram(d, n, disc.sector, intensity_count, joint_label, params.n_bin, joint_shapes, intensity_bins, out);
  }
  if (own_shape) {
    shapeHistogram(d, n, disc.sector, shape_label, n_shape, out + intensity_bins, dimension - intensity_bins);
    scaleToLength(out, intensity_bins, 1.0f);
    scaleToLength(out + intensity_bins, dimension - intensity_bins, static_cast<float>(params.shape_weight));
  }
  scaleToLength(out, dimension, 1.0f);
  return true;
}

}  // namespace risas

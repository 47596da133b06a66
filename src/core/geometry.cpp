#include "risas/geometry.hpp"

#include <vector>

namespace risas {

std::vector<float> rayFactors(int count, double centre, double focal) {
  std::vector<float> factors(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) factors[static_cast<size_t>(i)] = static_cast<float>((i - centre) / focal);
  return factors;
}

void backProject(const cv::Mat& depth_metres, const Intrinsics& intrinsics, cv::Mat& points) {
  CV_Assert(depth_metres.type() == CV_32FC1);
  points.create(depth_metres.size(), CV_32FC3);
  const std::vector<float> x_factor = rayFactors(depth_metres.cols, intrinsics.cx, intrinsics.fx);
  const std::vector<float> y_factor = rayFactors(depth_metres.rows, intrinsics.cy, intrinsics.fy);
  cv::parallel_for_(cv::Range(0, depth_metres.rows), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      const float y = y_factor[static_cast<size_t>(v)];
      const float* z = depth_metres.ptr<float>(v);
      cv::Vec3f* p = points.ptr<cv::Vec3f>(v);
      for (int u = 0; u < depth_metres.cols; ++u) {
        p[u] = cv::Vec3f(x_factor[static_cast<size_t>(u)] * z[u], y * z[u], z[u]);  // NaN depth gives a NaN point
      }
    }
  });
}

cv::Mat backProject(const cv::Mat& depth_metres, const Intrinsics& intrinsics) {
  cv::Mat points;
  backProject(depth_metres, intrinsics, points);
  return points;
}

void computeGeometry(const RgbdFrame& frame, const GeometryParams& params, FrameGeometry& geometry) {
  params.validate();
  geometry.depth = frame.depth();
  geometry.x_factor = rayFactors(frame.size().width, frame.intrinsics().cx, frame.intrinsics().fx);
  geometry.y_factor = rayFactors(frame.size().height, frame.intrinsics().cy, frame.intrinsics().fy);
  geometry.normal_stride = params.normal_stride;
  estimateNormals(frame.depth(), geometry.x_factor, geometry.y_factor, params, geometry.normals,
                  geometry.on_block_surface);
}

FrameGeometry computeGeometry(const RgbdFrame& frame, const GeometryParams& params) {
  FrameGeometry geometry;
  computeGeometry(frame, params, geometry);
  return geometry;
}

}  // namespace risas

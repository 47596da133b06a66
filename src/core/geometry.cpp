#include "risas/geometry.hpp"

namespace risas {

void backProject(const cv::Mat& depth_metres, const Intrinsics& intrinsics, cv::Mat& points) {
  CV_Assert(depth_metres.type() == CV_32FC1);
  points.create(depth_metres.size(), CV_32FC3);
  for (int v = 0; v < depth_metres.rows; ++v) {
    const float* z = depth_metres.ptr<float>(v);
    cv::Vec3f* p = points.ptr<cv::Vec3f>(v);
    for (int u = 0; u < depth_metres.cols; ++u) {
      const cv::Point3f q = intrinsics.backProject(static_cast<float>(u), static_cast<float>(v), z[u]);
      p[u] = cv::Vec3f(q.x, q.y, q.z);  // NaN depth gives a NaN point
    }
  }
}

cv::Mat backProject(const cv::Mat& depth_metres, const Intrinsics& intrinsics) {
  cv::Mat points;
  backProject(depth_metres, intrinsics, points);
  return points;
}

cv::Mat estimateNormals(const cv::Mat& points, const GeometryParams& params) {
  cv::Mat normals;
  estimateNormals(points, params, normals);
  return normals;
}

void computeGeometry(const RgbdFrame& frame, const GeometryParams& params, FrameGeometry& geometry) {
  params.validate();
  backProject(frame.depth(), frame.intrinsics(), geometry.points);
  estimateNormals(geometry.points, params, geometry.normals);
}

FrameGeometry computeGeometry(const RgbdFrame& frame, const GeometryParams& params) {
  FrameGeometry geometry;
  computeGeometry(frame, params, geometry);
  return geometry;
}

}  // namespace risas

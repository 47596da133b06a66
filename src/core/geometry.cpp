#include "risas/geometry.hpp"

namespace risas {

cv::Mat backProject(const cv::Mat& depth_metres, const Intrinsics& intrinsics) {
  CV_Assert(depth_metres.type() == CV_32FC1);
  cv::Mat points(depth_metres.size(), CV_32FC3);
  for (int v = 0; v < depth_metres.rows; ++v) {
    const float* z = depth_metres.ptr<float>(v);
    cv::Vec3f* p = points.ptr<cv::Vec3f>(v);
    for (int u = 0; u < depth_metres.cols; ++u) {
      const cv::Point3f q = intrinsics.backProject(static_cast<float>(u), static_cast<float>(v), z[u]);
      p[u] = cv::Vec3f(q.x, q.y, q.z);  // NaN depth gives a NaN point
    }
  }
  return points;
}

FrameGeometry computeGeometry(const RgbdFrame& frame, const GeometryParams& params) {
  params.validate();
  FrameGeometry geometry;
  geometry.points = backProject(frame.depth(), frame.intrinsics());
  geometry.normals = estimateNormals(geometry.points, params);
  return geometry;
}

}  // namespace risas

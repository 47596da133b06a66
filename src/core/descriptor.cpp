#include "risas/descriptor.hpp"

#include "risas/errors.hpp"
#include "risas/grey_noise.hpp"
#include "risas/neighbourhood.hpp"
#include "risas/orientation.hpp"
#include "risas/workspace.hpp"

#include <algorithm>
#include <cmath>

namespace risas {

Descriptor::Descriptor(const DescriptorParams& params) : params_(params), encoder_(params) {}

void Descriptor::compute(const RgbdFrame& frame, const FrameGeometry& geometry, std::vector<cv::KeyPoint>& keypoints,
                         cv::Mat& descriptors, std::vector<KeypointGeometry>* info) const {
  if (!geometry.fits(frame.size())) throw InputError("geometry does not belong to this frame");
  const Intrinsics& K = frame.intrinsics();
  // s_min and s_max of eq. 4 need the frame's depth range; the metric radius does not.
  const ScaleRange scales = params_.support_radius > 0.0 ? ScaleRange() : frameScaleRange(frame.depth());
  const float max_radius = std::hypot(static_cast<float>(frame.size().width), static_cast<float>(frame.size().height));
  // The grey image's coarser levels (sample_blur), in buffers kept from
  // frame to frame; the workspace keeps no header of the frame's own image.
  GreyPyramid& buffers = Workspace::ofThisThread().get<GreyPyramid>();
  buildGreyPyramid(frame.gray(), pyramidLevelsNeeded(params_), buffers);
  // The noise the ranks allow for (soft binning's only): the frame's own
  // unless the parameters give it.
  const bool estimated = params_.soft_binning && params_.grey_noise < 0.0;
  buffers.noise = static_cast<float>(estimated ? estimateGreyNoise(frame.gray()) : std::max(params_.grey_noise, 0.0));
  const GreyPyramid grey = buffers;
  buffers.level[0].release();
  const int n = static_cast<int>(keypoints.size());
  cv::Mat rows(n, descriptorSize(), CV_32F);
  std::vector<char> described(static_cast<size_t>(n), 0);
  std::vector<KeypointGeometry> geometries(static_cast<size_t>(n));

  const bool centroid_needed = intensityCentroidNeeded(params_);
  cv::parallel_for_(cv::Range(0, n), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      cv::KeyPoint& kp = keypoints[static_cast<size_t>(i)];
      const int u = cvRound(kp.pt.x), v = cvRound(kp.pt.y);
      if (u < 0 || v < 0 || u >= frame.size().width || v >= frame.size().height || !geometry.hasPoint(v, u)) continue;
      // A patch wider than the image gathers nothing more (and its radius
      // must stay in an int's range for the neighbourhood's loops).
      const float R = std::min(patchRadius(geometry.depth.at<float>(v, u), scales, params_.support_radius, K), max_radius);
      const auto nb = selectNeighbourhood(frame, geometry, kp.pt, R, params_.background_distance, centroid_needed);
      if (!nb) continue;
      Orientation orientation = dominantOrientation(*nb, K, params_);
      if (orientation.source == OrientationSource::Rejected) continue;
      const float radius = ellipseRadius(*nb, K, params_.min_radius_px, params_.max_radius_px);
      if (orientation.source == OrientationSource::IntensityCentroid && params_.gradient_orientation) {
        orientation.theta = gradientOrientation(grey, geometry, *nb, radius, params_);
      }
      if (!encoder_.encode(grey, geometry, *nb, radius, orientation.theta, rows.ptr<float>(i))) continue;

      double degrees = orientation.theta * 180.0 / CV_PI;
      if (degrees < 0.0) degrees += 360.0;
      kp.angle = static_cast<float>(degrees >= 360.0 ? 0.0 : degrees);
      kp.size = 2.0f * radius;
      const double focal = 0.5 * (K.fx + K.fy);
      geometries[static_cast<size_t>(i)] = {
          cv::Point3f(static_cast<float>(nb->point.x()), static_cast<float>(nb->point.y()),
                      static_cast<float>(nb->point.z())),
          cv::Vec3f(static_cast<float>(nb->normal.x()), static_cast<float>(nb->normal.y()),
                    static_cast<float>(nb->normal.z())),
          static_cast<float>(radius * nb->point.z() / focal)};
      described[static_cast<size_t>(i)] = 1;
    }
  });

  std::vector<cv::KeyPoint> kept;
  std::vector<KeypointGeometry> kept_info;
  cv::Mat kept_rows(0, descriptorSize(), CV_32F);
  for (int i = 0; i < n; ++i) {
    if (!described[static_cast<size_t>(i)]) continue;
    kept.push_back(keypoints[static_cast<size_t>(i)]);
    kept_info.push_back(geometries[static_cast<size_t>(i)]);
    kept_rows.push_back(rows.row(i));
  }
  keypoints.swap(kept);
  descriptors = kept_rows;
  if (info) info->swap(kept_info);
}

}  // namespace risas

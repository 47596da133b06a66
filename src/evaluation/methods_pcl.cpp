// The paper's PCL peers: CSHOT (pcl::SHOTColorEstimation) on keypoints from
// the RISAS detector, ISS (pcl::ISSKeypoint3D), uniform sampling
// (pcl::UniformSampling) and SIFT. Parameters are chosen for a Kinect at
// about 1 m (docs/evaluation.md lists them with the reasons):
//   - surface: the organised cloud at every second pixel (~2.5 mm apart at
//     1 m), normals by pcl::IntegralImageNormalEstimation (covariance,
//     depth-change factor 0.02, smoothing 10 px) on the full cloud;
//   - CSHOT support radius 0.05 m (about the RISAS patch: 20-30 px at 1 m);
//   - ISS on a 5 mm voxel grid: salient radius 6 x 5 mm, non-maximum radius
//     4 x 5 mm, thresholds 0.975, at least 5 neighbours (PCL's tutorial values
//     in units of the cloud resolution);
//   - uniform sampling with a 3 cm radius (a few hundred keypoints per frame).
// Everything runs single-threaded (the non-OMP classes).
#include "risas/evaluation/methods.hpp"

#include "risas/evaluation/protocol.hpp"
#include "risas/risas.hpp"

#include <opencv2/features2d.hpp>
#include <pcl/features/integral_image_normal.h>
#include <pcl/features/shot.h>
#include <pcl/filters/uniform_sampling.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/keypoints/iss_3d.h>
#include <pcl/console/print.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <cmath>

namespace risas::eval {
namespace {

using Point = pcl::PointXYZRGBA;
using Cloud = pcl::PointCloud<Point>;
using Normals = pcl::PointCloud<pcl::Normal>;

constexpr double kShotRadius = 0.05;
constexpr double kIssResolution = 0.005;
constexpr double kUniformRadius = 0.03;

Point makePoint(const cv::Point3f& p, const cv::Vec3b& bgr) {
  Point q;
  q.x = p.x;
  q.y = p.y;
  q.z = p.z;
  q.b = bgr[0];
  q.g = bgr[1];
  q.r = bgr[2];
  q.a = 255;
  return q;
}

// The frame as an organised coloured cloud (NaN where depth is missing).
Cloud::Ptr organisedCloud(const RgbdFrame& frame, const cv::Mat& bgr) {
  auto cloud = pcl::make_shared<Cloud>(frame.size().width, frame.size().height);
  cloud->is_dense = false;
  const Intrinsics& K = frame.intrinsics();
  for (int v = 0; v < frame.size().height; ++v) {
    for (int u = 0; u < frame.size().width; ++u) {
      const float z = frame.depth().at<float>(v, u);
      (*cloud)(u, v) = makePoint(K.backProject(static_cast<float>(u), static_cast<float>(v), z), bgr.at<cv::Vec3b>(v, u));
    }
  }
  return cloud;
}

// Keypoints as pixels, from 2D or 3D detectors.
class KeypointSource {
 public:
  virtual ~KeypointSource() = default;
  virtual std::vector<cv::Point2f> detect(const RgbdFrame& frame, const Cloud::ConstPtr& cloud) const = 0;
};

class RisasKeypoints : public KeypointSource {
 public:
  explicit RisasKeypoints(const RisasParams& params) : risas_(params) {}
  std::vector<cv::Point2f> detect(const RgbdFrame& frame, const Cloud::ConstPtr&) const override {
    std::vector<cv::KeyPoint> keypoints;
    risas_.detect(frame, keypoints);
    std::vector<cv::Point2f> pixels;
    for (const cv::KeyPoint& k : keypoints) pixels.push_back(k.pt);
    return pixels;
  }

 private:
  Risas risas_;
};

class SiftKeypoints : public KeypointSource {
 public:
  std::vector<cv::Point2f> detect(const RgbdFrame& frame, const Cloud::ConstPtr&) const override {
    std::vector<cv::KeyPoint> keypoints;
    sift_->detect(frame.gray(), keypoints);
    std::vector<cv::Point2f> pixels;
    for (const cv::KeyPoint& k : keypoints) pixels.push_back(k.pt);
    return pixels;
  }

 private:
  cv::Ptr<cv::SIFT> sift_ = cv::SIFT::create();
};

// 3D detectors give points; their pixels are their projections.
std::vector<cv::Point2f> project(const Cloud& points, const Intrinsics& K) {
  std::vector<cv::Point2f> pixels;
  for (const Point& p : points) {
    if (std::isfinite(p.z) && p.z > 0) pixels.push_back(K.project(cv::Point3f(p.x, p.y, p.z)));
  }
  return pixels;
}

Cloud::Ptr validPoints(const Cloud::ConstPtr& cloud) {
  auto dense = pcl::make_shared<Cloud>();
  for (const Point& p : *cloud) {
    if (std::isfinite(p.z)) dense->push_back(p);
  }
  return dense;
}

class IssKeypoints : public KeypointSource {
 public:
  std::vector<cv::Point2f> detect(const RgbdFrame& frame, const Cloud::ConstPtr& cloud) const override {
    pcl::VoxelGrid<Point> grid;
    grid.setInputCloud(validPoints(cloud));
    grid.setLeafSize(kIssResolution, kIssResolution, kIssResolution);
    auto voxels = pcl::make_shared<Cloud>();
    grid.filter(*voxels);
    pcl::ISSKeypoint3D<Point, Point> iss;
    iss.setInputCloud(voxels);
    iss.setSearchMethod(pcl::make_shared<pcl::search::KdTree<Point>>());
    iss.setSalientRadius(6 * kIssResolution);
    iss.setNonMaxRadius(4 * kIssResolution);
    iss.setThreshold21(0.975);
    iss.setThreshold32(0.975);
    iss.setMinNeighbors(5);
    iss.setNumberOfThreads(1);
    Cloud keypoints;
    iss.compute(keypoints);
    return project(keypoints, frame.intrinsics());
  }
};

class UniformKeypoints : public KeypointSource {
 public:
  std::vector<cv::Point2f> detect(const RgbdFrame& frame, const Cloud::ConstPtr& cloud) const override {
    pcl::UniformSampling<Point> sampling;
    sampling.setInputCloud(validPoints(cloud));
    sampling.setRadiusSearch(kUniformRadius);
    Cloud keypoints;
    sampling.filter(keypoints);
    return project(keypoints, frame.intrinsics());
  }
};

class CshotMethod : public FeatureMethod {
 public:
  CshotMethod(std::string name, std::unique_ptr<KeypointSource> source)
      : name_(std::move(name)), source_(std::move(source)) {
    // PCL reports every keypoint whose support has no valid reference frame;
    // those get NaN descriptors and are dropped below, so the lines are noise.
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  std::string name() const override { return name_; }
  int norm() const override { return cv::NORM_L2; }

  MethodOutput run(const RgbdFrame& frame, const cv::Mat& bgr) const override {
    const Cloud::ConstPtr cloud = organisedCloud(frame, bgr);
    const std::vector<cv::Point2f> pixels = source_->detect(frame, cloud);

    pcl::IntegralImageNormalEstimation<Point, pcl::Normal> normal_estimation;
    normal_estimation.setNormalEstimationMethod(normal_estimation.COVARIANCE_MATRIX);
    normal_estimation.setMaxDepthChangeFactor(0.02f);
    normal_estimation.setNormalSmoothingSize(10.0f);
    normal_estimation.setInputCloud(cloud);
    Normals normals;
    normal_estimation.compute(normals);

    // The search surface: every second pixel with a point and a normal.
    auto surface = pcl::make_shared<Cloud>();
    auto surface_normals = pcl::make_shared<Normals>();
    for (uint32_t v = 0; v < cloud->height; v += 2) {
      for (uint32_t u = 0; u < cloud->width; u += 2) {
        const Point& p = (*cloud)(u, v);
        const pcl::Normal& n = normals(u, v);
        if (!std::isfinite(p.z) || !std::isfinite(n.normal_x)) continue;
        surface->push_back(p);
        surface_normals->push_back(n);
      }
    }

    // Each keypoint at its protocol 3D point (median depth of 3x3).
    auto keypoints = pcl::make_shared<Cloud>();
    std::vector<cv::Point2f> kept_pixels;
    for (const cv::Point2f& px : pixels) {
      const cv::Point3f p = keypointPoint(frame.depth(), frame.intrinsics(), px);
      if (std::isnan(p.z)) continue;
      const int u = std::clamp(cvRound(px.x), 0, bgr.cols - 1), v = std::clamp(cvRound(px.y), 0, bgr.rows - 1);
      keypoints->push_back(makePoint(p, bgr.at<cv::Vec3b>(v, u)));
      kept_pixels.push_back(px);
    }

    MethodOutput out;
    if (keypoints->empty() || surface->empty()) {
      out.descriptors = cv::Mat(0, 1344, CV_32F);
      return out;
    }
    pcl::SHOTColorEstimation<Point, pcl::Normal, pcl::SHOT1344> cshot;
    cshot.setInputCloud(keypoints);
    cshot.setSearchSurface(surface);
    cshot.setInputNormals(surface_normals);
    cshot.setSearchMethod(pcl::make_shared<pcl::search::KdTree<Point>>());
    cshot.setRadiusSearch(kShotRadius);
    pcl::PointCloud<pcl::SHOT1344> descriptors;
    cshot.compute(descriptors);

    // Keypoints whose support held too few points get NaN descriptors: dropped.
    for (size_t i = 0; i < descriptors.size(); ++i) {
      const float* d = descriptors[i].descriptor;
      if (!std::all_of(d, d + 1344, [](float x) { return std::isfinite(x); })) continue;
      out.pixels.push_back(kept_pixels[i]);
      out.descriptors.push_back(cv::Mat(1, 1344, CV_32F, const_cast<float*>(d)).clone());
    }
    if (out.descriptors.empty()) out.descriptors = cv::Mat(0, 1344, CV_32F);
    return out;
  }

 private:
  std::string name_;
  std::unique_ptr<KeypointSource> source_;
};

}  // namespace

bool havePcl() { return true; }

std::unique_ptr<FeatureMethod> makePclMethod(const std::string& name, const RisasParams& params) {
  if (name == "RISAS+CSHOT") return std::make_unique<CshotMethod>(name, std::make_unique<RisasKeypoints>(params));
  if (name == "ISS+CSHOT") return std::make_unique<CshotMethod>(name, std::make_unique<IssKeypoints>());
  if (name == "UNIFORM+CSHOT") return std::make_unique<CshotMethod>(name, std::make_unique<UniformKeypoints>());
  if (name == "SIFT+CSHOT") return std::make_unique<CshotMethod>(name, std::make_unique<SiftKeypoints>());
  return nullptr;
}

}  // namespace risas::eval

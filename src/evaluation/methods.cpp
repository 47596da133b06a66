#include "risas/evaluation/methods.hpp"

#include "risas/errors.hpp"
#include "risas/evaluation/metrics.hpp"
#include "risas/risas.hpp"

#include <opencv2/features2d.hpp>

#include <utility>

namespace risas::eval {
namespace {

class RisasMethod : public FeatureMethod {
 public:
  RisasMethod(std::string name, const RisasParams& params) : name_(std::move(name)), risas_(params) {}
  std::string name() const override { return name_; }
  int norm() const override { return risas_.defaultNorm(); }
  MethodOutput run(const RgbdFrame& frame, const cv::Mat&) const override {
    const Features f = risas_.extract(frame);
    MethodOutput out;
    for (const cv::KeyPoint& k : f.keypoints) out.pixels.push_back(k.pt);
    out.descriptors = f.descriptors;
    return out;
  }

 private:
  std::string name_;
  Risas risas_;
};

std::vector<cv::KeyPoint> detectOn(const cv::Mat& gray, cv::Feature2D& detector, Keypoints which) {
  std::vector<cv::KeyPoint> keypoints;
  detector.detect(gray, keypoints);
  return which == Keypoints::OnePerImagePoint ? onePerImagePoint(std::move(keypoints)) : keypoints;
}

// An OpenCV Feature2D on the grey image.
class OpenCvMethod : public FeatureMethod {
 public:
  OpenCvMethod(std::string name, cv::Ptr<cv::Feature2D> feature, Keypoints which = Keypoints::All)
      : name_(std::move(name)), feature_(std::move(feature)), which_(which) {}
  std::string name() const override { return name_; }
  int norm() const override { return feature_->defaultNorm(); }
  MethodOutput run(const RgbdFrame& frame, const cv::Mat&) const override {
    std::vector<cv::KeyPoint> keypoints;
    MethodOutput out;
    detectAndDescribe(*feature_, frame.gray(), which_, keypoints, out.descriptors);
    for (const cv::KeyPoint& k : keypoints) out.pixels.push_back(k.pt);
    return out;
  }

 private:
  std::string name_;
  cv::Ptr<cv::Feature2D> feature_;
  Keypoints which_;
};

// Another detector's keypoints described by RISAS: which of the two stages
// limits a result (docs/evaluation.md).
class DescribedByRisas : public FeatureMethod {
 public:
  DescribedByRisas(std::string name, cv::Ptr<cv::Feature2D> detector, const RisasParams& params,
                   Keypoints which = Keypoints::All)
      : name_(std::move(name)), detector_(std::move(detector)), risas_(params), which_(which) {}
  std::string name() const override { return name_; }
  int norm() const override { return risas_.defaultNorm(); }
  MethodOutput run(const RgbdFrame& frame, const cv::Mat&) const override {
    std::vector<cv::KeyPoint> keypoints = detectOn(frame.gray(), *detector_, which_);
    MethodOutput out;
    risas_.compute(frame, keypoints, out.descriptors);
    for (const cv::KeyPoint& k : keypoints) out.pixels.push_back(k.pt);
    return out;
  }

 private:
  std::string name_;
  cv::Ptr<cv::Feature2D> detector_;
  Risas risas_;
  Keypoints which_;
};

}  // namespace

void detectAndDescribe(cv::Feature2D& feature, const cv::Mat& gray, Keypoints which,
                       std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
  if (which == Keypoints::All) {
    feature.detectAndCompute(gray, cv::noArray(), keypoints, descriptors);
    return;
  }
  keypoints = detectOn(gray, feature, which);
  feature.compute(gray, keypoints, descriptors);
}

std::vector<std::string> methodNames() {
  std::vector<std::string> names = {"RISAS", "ORB", "SIFT", "ORB+RISAS", "ORB-distinct", "ORB-distinct+RISAS"};
  if (havePcl()) {
    for (const char* n : {"RISAS+CSHOT", "ISS+CSHOT", "UNIFORM+CSHOT", "SIFT+CSHOT"}) names.push_back(n);
  }
  return names;
}

std::unique_ptr<FeatureMethod> makeRisas(const std::string& name, const RisasParams& params) {
  return std::make_unique<RisasMethod>(name, params);
}

std::unique_ptr<FeatureMethod> makeMethod(const std::string& name, const RisasParams& params) {
  if (name == "RISAS") return makeRisas(name, params);
  // ORB as the paper's peers and visual odometry use it: 1000 features.
  if (name == "ORB") return std::make_unique<OpenCvMethod>(name, cv::ORB::create(1000));
  if (name == "SIFT") return std::make_unique<OpenCvMethod>(name, cv::SIFT::create());
  if (name == "ORB+RISAS") return std::make_unique<DescribedByRisas>(name, cv::ORB::create(1000), params);
  if (name == "ORB-distinct") {
    return std::make_unique<OpenCvMethod>(name, cv::ORB::create(1000), Keypoints::OnePerImagePoint);
  }
  if (name == "ORB-distinct+RISAS") {
    return std::make_unique<DescribedByRisas>(name, cv::ORB::create(1000), params, Keypoints::OnePerImagePoint);
  }
  if (auto pcl = makePclMethod(name, params)) return pcl;
  std::string known;
  for (const std::string& n : methodNames()) known += " " + n;
  throw InputError("unknown method '" + name + "'" +
                   (name.find("CSHOT") != std::string::npos && !havePcl() ? " (this build has no PCL)" : "") +
                   "; known:" + known);
}

}  // namespace risas::eval

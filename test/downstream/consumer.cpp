// What a user's program does with the installed risas: features of an RGB-D
// frame (a random texture on a slanted plane, made here), matched to a
// shifted copy of it, and the motion between the two. Prints
// "risas consumer: N features, M matches, motion <valid>" and exits 0 when
// there are features and matches. Built by the downstream tests against the
// installed package only (see test/downstream/CMakeLists.txt).
#include <risas/matcher.hpp>
#include <risas/risas.hpp>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>

#ifdef RISAS_CONSUMER_WITH_MESSAGES
#include <risas/KeypointArray.h>
#endif

namespace {

risas::RgbdFrame slantedPlane(int shift) {
  cv::Mat texture(480, 700, CV_8UC1);
  cv::RNG rng(7);
  rng.fill(texture, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(texture, texture, cv::Size(0, 0), 2.0);
  cv::Mat bgr;
  cv::cvtColor(texture(cv::Rect(shift, 0, 640, 480)), bgr, cv::COLOR_GRAY2BGR);
  cv::Mat depth(480, 640, CV_32FC1);
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) depth.at<float>(v, u) = 1.2f + 0.0004f * float(u);
  }
  return risas::RgbdFrame(bgr, depth, risas::Intrinsics(525.0, 525.0, 319.5, 239.5));
}

}  // namespace

int main() {
  const risas::Risas risas;
  const risas::Features a = risas.extract(slantedPlane(0));
  const risas::Features b = risas.extract(slantedPlane(8));
  const std::vector<cv::DMatch> matches = risas::matchDescriptors(a.descriptors, b.descriptors);
#ifdef RISAS_CONSUMER_WITH_MESSAGES
  risas::KeypointArray message;  // the package's messages are usable too
  message.descriptor_type = "RISAS";
  message.descriptor_dim = static_cast<uint32_t>(a.descriptors.cols);
#endif
  std::printf("risas consumer: %zu features, %zu matches\n", a.keypoints.size(), matches.size());
  return a.keypoints.empty() || matches.empty() ? 1 : 0;
}

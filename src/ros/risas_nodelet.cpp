// risas/RisasNodelet: a thin ROS shell over the core library. It synchronises
// registered colour, depth and camera_info, runs RISAS on each frame, matches
// the frame to the previous one of the same camera frame, and publishes
//   ~keypoints  risas/KeypointArray (features, 3D points, descriptors)
//   ~image      bgr8 overlay: previous frame left, current right, RANSAC
//               inliers green, outliers red
//   ~points     sensor_msgs/PointCloud2 of the keypoints' 3D points (x, y, z,
//               response, normal_x/y/z), for rviz
//   ~motion     geometry_msgs/TransformStamped: the current camera frame in
//               the previous one (p_previous = T p_current), child_frame_id
//               the camera frame, frame_id the camera frame + "_previous"
// It subscribes only while someone listens (unless ~always_subscribe), with
// the transports ~image_transport (colour) and ~depth_image_transport (depth),
// both raw by default; a lossy depth transport or one that is not installed
// stops the nodelet at start with an error naming it. Colour and depth
// stamped more than 0.02 s apart are warned of (the depth shows another
// moment), and skipped beyond ~approximate_sync_max_interval when it is set.
#include "risas/errors.hpp"
#include "risas/matcher.hpp"
#include "risas/motion.hpp"
#include "risas/overlay.hpp"
#include "risas/risas.hpp"
#include "risas/ros/conversions.hpp"
#include "risas/ros/log_throttle.hpp"
#include "risas/ros/node_params.hpp"
#include "risas/ros/reconfigure.hpp"

#include <risas/KeypointArray.h>
#include <risas/RisasDescriptorConfig.h>
#include <risas/RisasDetectorConfig.h>
#include <risas/RisasMatchConfig.h>

#include <cv_bridge/cv_bridge.h>
#include <dynamic_reconfigure/server.h>
#include <geometry_msgs/TransformStamped.h>
#include <image_transport/image_transport.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/image_encodings.h>

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>

namespace risas_ros {

using risas::InputError;
using risas::MotionEstimate;
using risas::Risas;

namespace {

using sensor_msgs::CameraInfo;
using sensor_msgs::CameraInfoConstPtr;
using sensor_msgs::Image;
using sensor_msgs::ImageConstPtr;
using ApproximatePolicy = message_filters::sync_policies::ApproximateTime<Image, Image, CameraInfo>;
using ExactPolicy = message_filters::sync_policies::ExactTime<Image, Image, CameraInfo>;

}  // namespace

class RisasNodelet : public nodelet::Nodelet {
 public:
  RisasNodelet() = default;

 private:
  // What the next frame needs of the last one.
  struct PreviousFrame {
    std::string frame_id;
    cv::Mat gray;
    Features features;
  };

  // One consistent set of parameters and the extractor built from them;
  // replaced whole on reconfiguration, so a frame never sees half a change.
  struct Setup {
    RisasParams params;
    Risas risas;
    explicit Setup(const RisasParams& p) : params(p), risas(p) {}
  };

  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    bool approximate = true;
    rgb_it_ = std::make_unique<image_transport::ImageTransport>(nh);
    try {
      NodeParams params(pnh);
      queue_size_ = params.whole("queue_size", 5, 1, 1000);
      always_subscribe_ = params.flag("always_subscribe", false);
      approximate = params.flag("approximate_sync", true);
      max_sync_interval_ = params.number("approximate_sync_max_interval", 0.0, 0.0, 3600.0);
      setup_ = std::make_shared<const Setup>(params.risas());
      // As depth_image_proc: ~image_transport for colour, ~depth_image_transport for depth.
      const std::vector<std::string> loadable = rgb_it_->getLoadableTransports();
      rgb_hints_.emplace("raw", ros::TransportHints(), pnh, "image_transport");
      depth_hints_.emplace("raw", ros::TransportHints(), pnh, "depth_image_transport");
      checkImageTransport(rgb_hints_->getTransport(), "image_transport", false, loadable);
      checkImageTransport(depth_hints_->getTransport(), "depth_image_transport", true, loadable);
      // ~image's transport plugins read ~image/compressed/... and the like.
      params.readByOthers({"image_transport", "depth_image_transport", "image"});
      params.refuseUnread();
    } catch (const std::invalid_argument& e) {
      NODELET_FATAL("invalid RISAS parameter: %s", e.what());
      throw;
    }

    if (approximate) {
      approximate_sync_ = std::make_unique<message_filters::Synchronizer<ApproximatePolicy>>(
          ApproximatePolicy(queue_size_), sub_rgb_, sub_depth_, sub_info_);
      approximate_sync_->registerCallback(&RisasNodelet::onFrame, this);
    } else {
      exact_sync_ = std::make_unique<message_filters::Synchronizer<ExactPolicy>>(ExactPolicy(queue_size_), sub_rgb_,
                                                                                sub_depth_, sub_info_);
      exact_sync_->registerCallback(&RisasNodelet::onFrame, this);
    }

    {
      // Publishers fire connectCb while being advertised: hold it back until all exist.
      std::lock_guard<std::mutex> lock(connect_mutex_);
      const auto connect = [this](const auto&) { connectCb(); };
      pub_keypoints_ = pnh.advertise<KeypointArray>("keypoints", 5, connect, connect);
      pub_motion_ = pnh.advertise<geometry_msgs::TransformStamped>("motion", 5, connect, connect);
      pub_points_ = pnh.advertise<sensor_msgs::PointCloud2>("points", 5, connect, connect);
      image_transport::ImageTransport private_it(pnh);
      pub_image_ = private_it.advertise("image", 1, connect, connect);
    }

    // One server per section, on its namespace: ~detector/tau is one name.
    serveSection(detector_server_, "detector", &RisasParams::detector);
    serveSection(descriptor_server_, "descriptor", &RisasParams::descriptor);
    serveSection(match_server_, "match", &RisasParams::match);

    watchdog_ = pnh.createWallTimer(ros::WallDuration(5.0), [this](const ros::WallTimerEvent&) { watchdog(); });
    connectCb();
  }

  void connectCb() {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    const bool wanted = always_subscribe_ || pub_keypoints_.getNumSubscribers() > 0 ||
                        pub_motion_.getNumSubscribers() > 0 || pub_image_.getNumSubscribers() > 0 ||
                        pub_points_.getNumSubscribers() > 0;
    if (wanted == subscribed_) return;
    if (wanted) {
      sub_rgb_.subscribe(*rgb_it_, "rgb/image_rect_color", queue_size_, *rgb_hints_);
      sub_depth_.subscribe(*rgb_it_, "depth_registered/image_raw", queue_size_, *depth_hints_);
      sub_info_.subscribe(getNodeHandle(), "rgb/camera_info", queue_size_);
      last_frame_ = ros::WallTime::now();
      NODELET_DEBUG("subscribed to %s, %s, %s", sub_rgb_.getTopic().c_str(), sub_depth_.getTopic().c_str(),
                    sub_info_.getTopic().c_str());
    } else {
      sub_rgb_.unsubscribe();
      sub_depth_.unsubscribe();
      sub_info_.unsubscribe();
      std::lock_guard<std::mutex> frame_lock(frame_mutex_);
      previous_.reset();
    }
    subscribed_ = wanted;
  }

  // Starts the dynamic_reconfigure server of one section on ~<name>, seeded
  // with the parameter server's values so the .cfg defaults never overwrite
  // them. A change the library rejects (e.g. a descriptor over 2,048
  // dimensions) is logged and undone in the server too.
  template <class Config, class Section>
  void serveSection(std::unique_ptr<dynamic_reconfigure::Server<Config>>& server, const std::string& name,
                    Section RisasParams::*section) {
    server = std::make_unique<dynamic_reconfigure::Server<Config>>(reconfigure_mutex_,
                                                                   ros::NodeHandle(getPrivateNodeHandle(), name));
    server->updateConfig(toConfig<Config>(current()->params.*section));
    server->setCallback([this, section](Config& config, uint32_t) {
      RisasParams params = current()->params;
      const Section before = params.*section;
      params.*section = applyConfig(config, before);
      if (!reconfigure(params)) config = toConfig<Config>(before);
    });
  }

  // Replaces the setup; false (logged) when the library rejects `params`.
  bool reconfigure(const RisasParams& params) {
    try {
      auto setup = std::make_shared<const Setup>(params);
      std::lock_guard<std::mutex> lock(setup_mutex_);
      setup_ = std::move(setup);
      NODELET_INFO("reconfigured: tau %.2f, max_keypoints %d, gamma %.2f, n_pie %d, n_bin %d, n_vec %d, n_ring %d "
                   "(descriptor_dim %d), gradient_orientation %d",
                   params.detector.tau, params.detector.max_keypoints, params.descriptor.gamma,
                   params.descriptor.n_pie, params.descriptor.n_bin, params.descriptor.n_vec, params.descriptor.n_ring,
                   params.descriptor.dimension(), int(params.descriptor.gradient_orientation));
      return true;
    } catch (const std::invalid_argument& e) {
      NODELET_ERROR("reconfiguration rejected, parameters kept: %s", e.what());
      return false;
    }
  }

  std::shared_ptr<const Setup> current() const {
    std::lock_guard<std::mutex> lock(setup_mutex_);
    return setup_;
  }

  void watchdog() {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    if (!subscribed_ || (ros::WallTime::now() - last_frame_).toSec() < 5.0) return;
    NODELET_WARN("no synchronised frames for 5 s on %s, %s and %s: are all three published, with stamps close "
                 "together, depth registered to the colour camera?",
                 sub_rgb_.getTopic().c_str(), sub_depth_.getTopic().c_str(), sub_info_.getTopic().c_str());
  }

  void onFrame(const ImageConstPtr& rgb, const ImageConstPtr& depth, const CameraInfoConstPtr& info) {
    const auto start = std::chrono::steady_clock::now();
    {
      std::lock_guard<std::mutex> lock(connect_mutex_);
      last_frame_ = ros::WallTime::now();
    }
    const std::shared_ptr<const Setup> setup = current();
    // One key for every interval: the text changes with each pair's stamps.
    try {
      const std::string warning = checkOneMoment(rgb->header, depth->header, max_sync_interval_);
      if (!warning.empty() && throttle_.shouldLog("stamps apart")) NODELET_WARN("%s", warning.c_str());
    } catch (const InputError& e) {
      if (throttle_.shouldLog("stamps beyond the bound")) NODELET_ERROR("skipping frame: %s", e.what());
      return;
    }
    std::optional<RgbdFrame> frame;
    try {
      frame.emplace(frameFromMessages(*rgb, *depth, *info));
    } catch (const InputError& e) {
      if (throttle_.shouldLog(e.what())) NODELET_ERROR("skipping frame: %s", e.what());
      return;
    }
    // Described all the same, for users who want the features alone.
    if (!isTfFrameId(rgb->header.frame_id) && throttle_.shouldLog("frame id")) {
      NODELET_WARN("colour frame_id '%s' is no tf frame id (empty, or a leading '/'): the keypoints, ~points and "
                   "~motion are published but cannot be placed on tf",
                   rgb->header.frame_id.c_str());
    }
    Features features = setup->risas.extract(*frame);
    pub_keypoints_.publish(toMessage(features, rgb->header, *info));
    if (pub_points_.getNumSubscribers() > 0) pub_points_.publish(toPointCloud(features, rgb->header));

    std::lock_guard<std::mutex> lock(frame_mutex_);
    std::vector<cv::DMatch> matches;
    MotionEstimate motion;
    if (previous_ && previous_->frame_id != rgb->header.frame_id) {
      // Two cameras on the same topics: a motion between them means nothing.
      if (throttle_.shouldLog("camera changed")) {
        NODELET_WARN("camera frame changed from '%s' to '%s': not matching across the change",
                     previous_->frame_id.c_str(), rgb->header.frame_id.c_str());
      }
    } else if (previous_ && (previous_->features.descriptors.cols != features.descriptors.cols ||
                             !risas::layoutsAgree(previous_->features.descriptor_layout, features.descriptor_layout))) {
      NODELET_INFO("descriptor changed to %d-d, layout '%s': not matching across the change",
                   features.descriptors.cols, features.descriptor_layout.c_str());
    } else if (previous_) {
      matches = risas::matchDescriptors(features.descriptors, previous_->features.descriptors, setup->params.match);
      motion = risas::estimateRigidMotion(features.points(), previous_->features.points(), matches, setup->params.motion);
      if (motion.valid) {
        geometry_msgs::TransformStamped message;
        message.header.stamp = rgb->header.stamp;
        message.header.frame_id = rgb->header.frame_id + "_previous";
        message.child_frame_id = rgb->header.frame_id;
        message.transform = toTransform(motion.train_T_query);
        pub_motion_.publish(message);
      }
    }
    if (pub_image_.getNumSubscribers() > 0) {
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      std::ostringstream caption;
      caption.precision(1);
      caption << std::fixed << "RISAS  " << features.keypoints.size() << " features  " << matches.size()
              << " matches  " << motion.num_inliers << " inliers  " << ms << " ms";
      const cv::Mat& left = previous_ ? previous_->gray : frame->gray();
      const std::vector<cv::KeyPoint> none;
      const cv::Mat overlay = risas::drawMatchOverlay(left, previous_ ? previous_->features.keypoints : none, frame->gray(),
                                               features.keypoints, matches, motion.inliers, caption.str());
      pub_image_.publish(cv_bridge::CvImage(rgb->header, sensor_msgs::image_encodings::BGR8, overlay).toImageMsg());
    }
    previous_ = PreviousFrame{rgb->header.frame_id, frame->gray(), std::move(features)};
  }

  // Subscriptions and their synchronisation.
  std::unique_ptr<image_transport::ImageTransport> rgb_it_;
  std::optional<image_transport::TransportHints> rgb_hints_, depth_hints_;
  image_transport::SubscriberFilter sub_rgb_, sub_depth_;
  message_filters::Subscriber<CameraInfo> sub_info_;
  std::unique_ptr<message_filters::Synchronizer<ApproximatePolicy>> approximate_sync_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_sync_;
  int queue_size_ = 5;
  double max_sync_interval_ = 0.0;  // s; 0: no bound
  bool always_subscribe_ = false;

  std::mutex connect_mutex_;  // guards subscribed_, last_frame_ and the (un)subscribing
  bool subscribed_ = false;
  ros::WallTime last_frame_;
  ros::WallTimer watchdog_;

  ros::Publisher pub_keypoints_, pub_motion_, pub_points_;
  image_transport::Publisher pub_image_;

  mutable std::mutex setup_mutex_;
  std::shared_ptr<const Setup> setup_;
  boost::recursive_mutex reconfigure_mutex_;  // one for the three servers: changes apply one at a time
  std::unique_ptr<dynamic_reconfigure::Server<risas::RisasDetectorConfig>> detector_server_;
  std::unique_ptr<dynamic_reconfigure::Server<risas::RisasDescriptorConfig>> descriptor_server_;
  std::unique_ptr<dynamic_reconfigure::Server<risas::RisasMatchConfig>> match_server_;

  LogThrottle throttle_{5.0};  // each problem (an error's text, or a warning's key) at most every 5 s
  std::mutex frame_mutex_;  // frames are matched in arrival order, one at a time
  std::optional<PreviousFrame> previous_;
};

}  // namespace risas_ros

PLUGINLIB_EXPORT_CLASS(risas_ros::RisasNodelet, nodelet::Nodelet)

// A node's own parameters (~queue_size, ~approximate_sync, ~frame_id, ...)
// read as strictly as the algorithm's (paramsFromServer): the value given or
// a one-line std::invalid_argument naming it, never the default in silence.
// roscpp's NodeHandle::param falls back to the default when the type is not
// the one asked for, so `_approximate_sync:=0` (an int on the server) would
// leave approximate sync on.
#pragma once

#include "risas/params.hpp"

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

namespace risas_ros {

// The value of a parameter named `name` (for messages, e.g. "~queue_size"):
// a flag is true, false, 0 or 1; an int a whole number within [lo, hi]; a
// number a finite one within [lo, hi]; text a string, or a whole number
// (a device serial in a launch file's <param value> is one) as its digits.
bool flagValue(const std::string& name, XmlRpc::XmlRpcValue& value);
int intValue(const std::string& name, XmlRpc::XmlRpcValue& value, int lo, int hi);
double numberValue(const std::string& name, XmlRpc::XmlRpcValue& value, double lo, double hi);
std::string textValue(const std::string& name, XmlRpc::XmlRpcValue& value);
// A tf frame id: not empty and without a leading '/', which tf2 refuses in
// every lookup (an empty frame, or ROS 1 Groovy's "/odom").
bool isTfFrameId(const std::string& id);
inline const char* const kTfFrameIdRule = "a tf frame id: not empty, no leading '/'";
std::string frameIdValue(const std::string& name, XmlRpc::XmlRpcValue& value);
// std::invalid_argument when two of the (name, frame id) pairs, empty ids
// left out, name one frame: a node would publish a frame as its own parent,
// which tf2 refuses at every listener.
void requireDistinctFrames(const std::vector<std::pair<std::string, std::string>>& frames);

// A node's private namespace read whole: each parameter as above (the
// fallback when it is not set), the algorithm's sections by
// paramsFromServer, and then every name under the namespace that nothing
// read refused by name. roscpp leaves such a name unread in silence: a
// misspelt ~aproximate_sync kept the default, and openni2_camera's
// ~color_mode given to this package's camera did nothing.
class NodeParams {
 public:
  // pnh: the nodelet's private handle. A standalone node's nodelet::Loader
  // reads ~num_worker_threads there (the node and its one nodelet share a
  // name); in a manager the manager reads its own, so the nodelet's is
  // unread like any other.
  explicit NodeParams(const ros::NodeHandle& pnh);

  bool flag(const std::string& key, bool fallback);
  int whole(const std::string& key, int fallback, int lo, int hi);
  double number(const std::string& key, double fallback, double lo, double hi);
  std::string text(const std::string& key, const std::string& fallback);
  std::string frameId(const std::string& key, const std::string& fallback);
  risas::RisasParams risas();  // paramsFromServer
  // Names that others read under the namespace: image_transport's hints
  // (~image_transport), a publisher's transport plugins (~image/compressed/...).
  void readByOthers(const std::vector<std::string>& keys);
  // std::invalid_argument naming the first name under the namespace that no
  // one reads, with the names that are read.
  void refuseUnread() const;

 private:
  ros::NodeHandle pnh_;
  std::set<std::string> read_;
};

// The first-level names under `ns` among the server's `names` (full names,
// as ros::param::getParamNames gives them) that are not in `read`, sorted.
std::vector<std::string> unreadNames(const std::vector<std::string>& names, const std::string& ns,
                                     const std::set<std::string>& read);

}  // namespace risas_ros

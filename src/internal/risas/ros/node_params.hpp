// A node's own parameters (~queue_size, ~approximate_sync, ~frame_id, ...)
// read as strictly as the algorithm's (paramsFromServer): the value given or
// a one-line std::invalid_argument naming it, never the default in silence.
// roscpp's NodeHandle::param falls back to the default when the type is not
// the one asked for, so `_approximate_sync:=0` (an int on the server) would
// leave approximate sync on.
#pragma once

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <string>

namespace risas_ros {

// The value of a parameter named `name` (for messages, e.g. "~queue_size"):
// a flag is true, false, 0 or 1; an int a whole number within [lo, hi]; a
// number a finite one within [lo, hi]; text a string, or a whole number
// (a device serial in a launch file's <param value> is one) as its digits.
bool flagValue(const std::string& name, XmlRpc::XmlRpcValue& value);
int intValue(const std::string& name, XmlRpc::XmlRpcValue& value, int lo, int hi);
double numberValue(const std::string& name, XmlRpc::XmlRpcValue& value, double lo, double hi);
std::string textValue(const std::string& name, XmlRpc::XmlRpcValue& value);

// The same from `nh`'s parameter `key`, `fallback` when it is not set.
bool flagParam(const ros::NodeHandle& nh, const std::string& key, bool fallback);
int intParam(const ros::NodeHandle& nh, const std::string& key, int fallback, int lo, int hi);
double numberParam(const ros::NodeHandle& nh, const std::string& key, double fallback, double lo, double hi);
std::string textParam(const ros::NodeHandle& nh, const std::string& key, const std::string& fallback);

}  // namespace risas_ros

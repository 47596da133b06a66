#include "risas/ros/node_params.hpp"

#include "risas/params_fields.hpp"
#include "risas/ros/conversions.hpp"

#include <ros/param.h>
#include <ros/this_node.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace risas_ros {
namespace {

[[noreturn]] void refuse(const std::string& name, const std::string& wanted, XmlRpc::XmlRpcValue& value) {
  throw std::invalid_argument(name + " must be " + wanted + " (got " + value.toXml() + ")");
}

bool isNumber(const XmlRpc::XmlRpcValue& value) {
  return value.getType() == XmlRpc::XmlRpcValue::TypeInt || value.getType() == XmlRpc::XmlRpcValue::TypeDouble;
}

double asDouble(XmlRpc::XmlRpcValue& value) {
  return value.getType() == XmlRpc::XmlRpcValue::TypeInt ? static_cast<int>(value) : static_cast<double>(value);
}

std::string range(double lo, double hi) {
  std::ostringstream text;
  text << "[" << lo << ", " << hi << "]";
  return text.str();
}

// read(name, value) of the parameter on the server, fallback when it is not set.
template <class T, class Read>
T fromServer(const ros::NodeHandle& nh, const std::string& key, const T& fallback, Read read) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(key, value)) return fallback;
  return read("~" + key, value);
}

}  // namespace

bool flagValue(const std::string& name, XmlRpc::XmlRpcValue& value) {
  if (value.getType() == XmlRpc::XmlRpcValue::TypeBoolean) return static_cast<bool>(value);
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) {
    const int v = static_cast<int>(value);
    if (v == 0 || v == 1) return v == 1;
  }
  refuse(name, "a flag: true, false, 0 or 1", value);
}

int intValue(const std::string& name, XmlRpc::XmlRpcValue& value, int lo, int hi) {
  const std::string wanted = "a whole number in " + range(lo, hi);
  if (!isNumber(value)) refuse(name, wanted, value);
  const double v = asDouble(value);
  if (!(v >= lo && v <= hi) || v != std::floor(v)) refuse(name, wanted, value);
  return static_cast<int>(v);
}

double numberValue(const std::string& name, XmlRpc::XmlRpcValue& value, double lo, double hi) {
  const std::string wanted = "a number in " + range(lo, hi);
  if (!isNumber(value)) refuse(name, wanted, value);
  const double v = asDouble(value);
  if (!(v >= lo && v <= hi)) refuse(name, wanted, value);
  return v;
}

std::string textValue(const std::string& name, XmlRpc::XmlRpcValue& value) {
  // A launch file's <param value="1208180007"/> (a device's serial) is an int.
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) return std::to_string(static_cast<int>(value));
  if (value.getType() != XmlRpc::XmlRpcValue::TypeString) refuse(name, "text", value);
  return static_cast<std::string>(value);
}

bool isTfFrameId(const std::string& id) { return !id.empty() && id.front() != '/'; }

std::string frameIdValue(const std::string& name, XmlRpc::XmlRpcValue& value) {
  const std::string id = textValue(name, value);
  if (!isTfFrameId(id)) refuse(name, kTfFrameIdRule, value);
  return id;
}

void requireDistinctFrames(const std::vector<std::pair<std::string, std::string>>& frames) {
  for (size_t i = 0; i < frames.size(); ++i) {
    for (size_t j = i + 1; j < frames.size(); ++j) {
      if (!frames[i].second.empty() && frames[i].second == frames[j].second) {
        throw std::invalid_argument(frames[i].first + " and " + frames[j].first + " name one frame '" +
                                    frames[i].second + "': they must differ");
      }
    }
  }
}

NodeParams::NodeParams(const ros::NodeHandle& pnh) : pnh_(pnh) {
  if (pnh_.getNamespace() == ros::this_node::getName()) read_.insert("num_worker_threads");
}

bool NodeParams::flag(const std::string& key, bool fallback) {
  read_.insert(key);
  return fromServer(pnh_, key, fallback, flagValue);
}

int NodeParams::whole(const std::string& key, int fallback, int lo, int hi) {
  read_.insert(key);
  return fromServer(pnh_, key, fallback,
                    [&](const std::string& name, XmlRpc::XmlRpcValue& v) { return intValue(name, v, lo, hi); });
}

double NodeParams::number(const std::string& key, double fallback, double lo, double hi) {
  read_.insert(key);
  return fromServer(pnh_, key, fallback,
                    [&](const std::string& name, XmlRpc::XmlRpcValue& v) { return numberValue(name, v, lo, hi); });
}

std::string NodeParams::text(const std::string& key, const std::string& fallback) {
  read_.insert(key);
  return fromServer(pnh_, key, fallback, textValue);
}

std::string NodeParams::frameId(const std::string& key, const std::string& fallback) {
  read_.insert(key);
  return fromServer(pnh_, key, fallback, frameIdValue);
}

risas::RisasParams NodeParams::risas() {
  risas::RisasParams names;
  risas::visitSections(names, [&](const char* section, const auto&) { read_.insert(section); });
  return paramsFromServer(pnh_);
}

void NodeParams::readByOthers(const std::vector<std::string>& keys) { read_.insert(keys.begin(), keys.end()); }

void NodeParams::refuseUnread() const {
  std::vector<std::string> names;
  if (!ros::param::getParamNames(names)) return;  // no master to ask: nothing to check against
  const std::vector<std::string> unread = unreadNames(names, pnh_.getNamespace(), read_);
  if (unread.empty()) return;
  std::string known;
  for (const std::string& name : read_) known += (known.empty() ? "" : ", ") + name;
  throw std::invalid_argument("unknown parameter ~" + unread.front() + " (a typo?); this node reads " + known);
}

std::vector<std::string> unreadNames(const std::vector<std::string>& names, const std::string& ns,
                                     const std::set<std::string>& read) {
  const std::string prefix = ns == "/" ? ns : ns + "/";
  std::set<std::string> unread;
  for (const std::string& name : names) {
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string first = name.substr(prefix.size(), name.find('/', prefix.size()) - prefix.size());
    if (!first.empty() && read.count(first) == 0) unread.insert(first);
  }
  return {unread.begin(), unread.end()};
}

}  // namespace risas_ros

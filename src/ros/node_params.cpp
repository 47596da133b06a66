#include "risas/ros/node_params.hpp"

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

bool flagParam(const ros::NodeHandle& nh, const std::string& key, bool fallback) {
  return fromServer(nh, key, fallback, flagValue);
}

int intParam(const ros::NodeHandle& nh, const std::string& key, int fallback, int lo, int hi) {
  return fromServer(nh, key, fallback, [&](const std::string& name, XmlRpc::XmlRpcValue& v) { return intValue(name, v, lo, hi); });
}

double numberParam(const ros::NodeHandle& nh, const std::string& key, double fallback, double lo, double hi) {
  return fromServer(nh, key, fallback,
                    [&](const std::string& name, XmlRpc::XmlRpcValue& v) { return numberValue(name, v, lo, hi); });
}

std::string textParam(const ros::NodeHandle& nh, const std::string& key, const std::string& fallback) {
  return fromServer(nh, key, fallback, textValue);
}

}  // namespace risas_ros

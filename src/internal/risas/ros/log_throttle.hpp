// Throttling for a stream of bad input: a new problem is reported at once, the
// same problem again only after `period` (a camera sending wrong frames at
// 30 Hz must not flood the log, but a second, different fault must not hide
// behind the first).
#pragma once

#include <ros/time.h>

#include <mutex>
#include <string>

namespace risas_ros {

class LogThrottle {
 public:
  explicit LogThrottle(double period_seconds) : period_(period_seconds) {}

  bool shouldLog(const std::string& message) {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::WallTime now = ros::WallTime::now();
    if (message == last_message_ && (now - last_time_).toSec() < period_) return false;
    last_message_ = message;
    last_time_ = now;
    return true;
  }

 private:
  std::mutex mutex_;
  double period_;
  std::string last_message_;
  ros::WallTime last_time_;
};

}  // namespace risas_ros

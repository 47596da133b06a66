// Throttling for a stream of bad input: a new problem is reported at once, the
// same problem again only after `period` (a camera sending wrong frames at
// 30 Hz must not flood the log, but a second, different fault must not hide
// behind the first). Each problem keeps its own time, so two faults that
// alternate frame by frame (two cameras on one topic, each wrong in its own
// way) are each reported once a period, not on every frame.
#pragma once

#include <ros/time.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <string>

namespace risas_ros {

class LogThrottle {
 public:
  explicit LogThrottle(double period_seconds) : period_(period_seconds) {}

  bool shouldLog(const std::string& message) {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::WallTime now = ros::WallTime::now();
    const auto known = last_time_.find(message);
    if (known != last_time_.end() && (now - known->second).toSec() < period_) return false;
    // Messages that name values (sizes, stamps) are many: the oldest is forgotten.
    if (known == last_time_.end() && last_time_.size() >= kKept) {
      last_time_.erase(std::min_element(last_time_.begin(), last_time_.end(),
                                        [](const auto& a, const auto& b) { return a.second < b.second; }));
    }
    last_time_[message] = now;
    return true;
  }

 private:
  static constexpr size_t kKept = 64;
  std::mutex mutex_;
  double period_;
  std::map<std::string, ros::WallTime> last_time_;  // when each problem was last reported
};

}  // namespace risas_ros

// The thread sanitizer stage's check of itself, run as a test that passes
// only on ThreadSanitizer's report: parallel_for_ bodies write one int
// without synchronisation. With the preloaded std::thread backend the report
// comes; if it did not, the stage could not see a race in risas's own loop
// bodies either.
#include <opencv2/core/utility.hpp>

#include <chrono>
#include <cstdio>
#include <thread>

int main() {
  cv::setNumThreads(4);
  int shared = 0;
  // Four stripes that each wait first, so that they run on four threads
  // rather than one thread taking all of them before the others start.
  cv::parallel_for_(cv::Range(0, 4), [&](const cv::Range& range) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    for (int i = range.start; i < range.end; ++i) shared += i;  // the race
  }, 4);
  std::printf("sum %d on %d threads\n", shared, cv::getNumThreads());
  return 0;
}

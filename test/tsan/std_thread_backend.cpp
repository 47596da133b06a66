// Preloaded into every process of the thread sanitizer stage
// (scripts/test.sh): OpenCV's parallel_for_ on plain std::threads, started
// and joined in each call.
//
// Why: Debian's OpenCV runs parallel_for_ on TBB, whose hand-offs use its
// own uninstrumented atomics. ThreadSanitizer cannot see them, so every loop
// body would seem to read what its caller wrote "without synchronisation"
// (docs/thread-safety.md). pthread_create and pthread_join it does see: the
// bodies still run in parallel, on as many threads as OpenCV's count (the
// machine's cores unless cv::setNumThreads says otherwise), and a real race
// between them is still reported (test/tsan/race_in_parallel_body.cpp).
#include <opencv2/core/parallel/parallel_backend.hpp>

#include <atomic>
#include <memory>
#include <thread>
#include <vector>

namespace {

thread_local int thread_index = 0;

class StdThreads : public cv::parallel::ParallelForAPI {
 public:
  void parallel_for(int tasks, FN_parallel_for_body_cb_t body, void* data) override {
    std::atomic<int> next{0};
    const auto work = [&](int index) {
      thread_index = index;
      for (int t; (t = next++) < tasks;) body(t, t + 1, data);
    };
    std::vector<std::thread> pool;
    for (int i = 1; i < threads_; ++i) pool.emplace_back(work, i);
    work(0);
    for (std::thread& thread : pool) thread.join();
  }
  int getThreadNum() const override { return thread_index; }
  int getNumThreads() const override { return threads_; }
  // OpenCV passes its count on at once (setParallelForBackend propagates
  // it), then at each cv::setNumThreads; below 2 it runs loops itself.
  int setNumThreads(int n) override {
    const int old = threads_;
    threads_ = n > 0 ? n : 1;
    return old;
  }
  const char* getName() const override { return "std::thread (risas TSan stage)"; }

 private:
  int threads_ = 1;
};

__attribute__((constructor)) void useStdThreads() {
  cv::parallel::setParallelForBackend(std::make_shared<StdThreads>());
}

}  // namespace

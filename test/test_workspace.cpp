// The per-thread workspace (risas/workspace.hpp): the stages keep their
// buffers there, made at a thread's first frame, reused after, freed with
// the thread.
#include "synthetic_fixtures.hpp"

#include "risas/risas.hpp"
#include "risas/workspace.hpp"

#include <gtest/gtest.h>
#include <opencv2/core/utility.hpp>

#include <malloc.h>

#include <thread>

namespace risas {
namespace {

// ASan and TSan bring allocators of their own.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitizedAllocator = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
constexpr bool kSanitizedAllocator = true;
#else
constexpr bool kSanitizedAllocator = false;
#endif
#else
constexpr bool kSanitizedAllocator = false;
#endif

// Runs f on a new thread and waits for it.
template <class F>
void onNewThread(F&& f) {
  std::thread thread(std::forward<F>(f));
  thread.join();
}

TEST(Workspace, HoldsEveryStagesBuffersReusesThemAndIsFreedWithItsThread) {
  const RgbdFrame frame = test::renderFrame(SyntheticScene::demo(), test::demoCamera());
  const Risas risas;
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);  // all stripes on the calling thread, whose workspace is looked at
  const Features reference = risas.extract(frame);  // this thread's workspace made
  const int before = Workspace::live();
  size_t after_first = 0, after_second = 0;
  int live_inside = 0;
  onNewThread([&] {
    EXPECT_EQ(Workspace::ofThisThread().size(), 0u);
    const Features first = risas.extract(frame);
    after_first = Workspace::ofThisThread().size();
    const Features second = risas.extract(frame);
    after_second = Workspace::ofThisThread().size();
    live_inside = Workspace::live();
    // Buffers reused as the last frame left them change nothing.
    EXPECT_EQ(cv::norm(first.descriptors, second.descriptors, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(first.descriptors, reference.descriptors, cv::NORM_INF), 0.0);
  });
  cv::setNumThreads(threads);
  // Geometry, normals (grid rows, bands), main normal, P's grid and image rows,
  // the eq. 1 kernel's stripe, the response, NMS, the grey pyramid, disc
  // samples, histogram, the gradient orientation's grid.
  EXPECT_EQ(after_first, 13u);
  EXPECT_EQ(after_second, after_first) << "a second frame made new buffers";
  EXPECT_EQ(live_inside, before + 1);
  EXPECT_EQ(Workspace::live(), before) << "the thread's workspace outlived it";
}

TEST(Workspace, AFrameHoldsAFewMegabytesAtVga) {
  // What a thread keeps after one VGA frame (docs/performance.md gives the
  // measured figure): more than the response image alone, less than 64 MB.
  const RgbdFrame frame = test::renderFrame(SyntheticScene::demo(), test::demoCamera());
  ASSERT_EQ(frame.size(), cv::Size(640, 480));
  if (kSanitizedAllocator) GTEST_SKIP() << "a sanitizer's allocator: glibc's malloc statistics do not see it";
  const Risas risas;
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  size_t held = 0;
  onNewThread([&] {
    const size_t start = mallinfo2().uordblks;
    { const Features f = risas.extract(frame); }
    held = mallinfo2().uordblks - start;
  });
  cv::setNumThreads(threads);
  EXPECT_GT(held, size_t(640 * 480 * 4));
  EXPECT_LT(held, size_t(64) << 20);
  std::printf("one thread's workspace after a VGA frame: %.1f MB\n", held / 1048576.0);
}

}  // namespace
}  // namespace risas

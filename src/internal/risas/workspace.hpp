// The buffers the stages keep from frame to frame, in one place: one
// Workspace per thread. Allocated afresh for every frame, a frame's images
// cost more in page faults than the work on them, so each stage takes its
// buffers from the workspace of the thread it runs on and leaves them there,
// sized for the largest frame the thread has seen.
//
// What a thread's workspace holds (each stage's buffer type, named where the
// stage is), at VGA with the defaults (normal_stride 2), measured in
// docs/performance.md ("Per-thread memory"):
//   calling thread  FrameGeometry (Risas: the frame's depth view, back-projection
//                   factors, normals), NormalBuffers (the normals' grid cloud and
//                   label images), the main normal's bins and P's grid inputs,
//                   ResponseBuffers (P's grid and R), the NMS candidates, the
//                   grey pyramid's coarse levels;
//   every thread of cv::parallel_for_ (the caller among them)
//                   the descriptor's disc samples, histogram and orientation
//                   grid (OrientationBuffers, kernels/gradient_orientation.cpp),
//                   and the row buffers of the normals' bands and grid rows, of
//                   P's smoothing, and of the eq. 1 kernel (its window ring and
//                   the grey and P rows).
// Lifetime: made at the thread's first frame, freed when the thread ends
// (cv::parallel_for_'s pool threads live until the process ends). The frame
// itself is never kept: Risas lets go of the depth view after each call.
#pragma once

#include <memory>
#include <typeindex>
#include <unordered_map>

namespace risas {

class Workspace {
 public:
  // This thread's workspace.
  static Workspace& ofThisThread();

  // The one T of this workspace, default-constructed at its first use and
  // returned as the last user left it.
  template <class T>
  T& get() {
    std::unique_ptr<Slot>& slot = slots_[std::type_index(typeid(T))];
    if (!slot) slot = std::make_unique<Holder<T>>();
    return static_cast<Holder<T>&>(*slot).value;
  }

  // How many buffer types it holds; how many workspaces the process holds.
  size_t size() const { return slots_.size(); }
  static int live();

  Workspace();
  ~Workspace();
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;

 private:
  struct Slot {
    virtual ~Slot() = default;
  };
  template <class T>
  struct Holder : Slot {
    T value;
  };
  std::unordered_map<std::type_index, std::unique_ptr<Slot>> slots_;
};

}  // namespace risas

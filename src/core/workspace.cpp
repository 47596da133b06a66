#include "risas/workspace.hpp"

#include <atomic>

namespace risas {
namespace {
std::atomic<int> live_workspaces{0};
}  // namespace

Workspace& Workspace::ofThisThread() {
  thread_local Workspace workspace;  // the library's only thread_local
  return workspace;
}

Workspace::Workspace() { ++live_workspaces; }
Workspace::~Workspace() { --live_workspaces; }
int Workspace::live() { return live_workspaces.load(); }

}  // namespace risas

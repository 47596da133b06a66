// Built instead of methods_pcl.cpp when PCL is absent: no CSHOT peers.
#include "risas/evaluation/methods.hpp"

namespace risas::eval {

bool havePcl() { return false; }

std::unique_ptr<FeatureMethod> makePclMethod(const std::string&, const RisasParams&) { return nullptr; }

}  // namespace risas::eval

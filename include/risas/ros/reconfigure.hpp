// The dynamic_reconfigure fields of risas/RisasNodelet (cfg/Risas.cfg) and
// the RisasParams fields they stand for: one list for both directions.
#pragma once

#include "risas/params.hpp"

#include <risas/RisasConfig.h>

namespace risas_ros {

template <class F>
void forEachReconfigurable(risas::RisasConfig& c, risas::RisasParams& p, F&& f) {
  f(c.tau, p.detector.tau);
  f(c.response_threshold, p.detector.response_threshold);
  f(c.max_keypoints, p.detector.max_keypoints);
  f(c.gamma, p.descriptor.gamma);
  f(c.n_pie, p.descriptor.n_pie);
  f(c.n_bin, p.descriptor.n_bin);
  f(c.n_vec, p.descriptor.n_vec);
  f(c.rho_threshold, p.descriptor.rho_threshold);
  f(c.support_radius, p.descriptor.support_radius);
  f(c.ratio, p.match.ratio);
}

inline risas::RisasConfig toConfig(risas::RisasParams params) {
  risas::RisasConfig config = risas::RisasConfig::__getDefault__();
  forEachReconfigurable(config, params, [](auto& field, const auto& value) { field = value; });
  return config;
}

inline risas::RisasParams applyConfig(risas::RisasConfig config, risas::RisasParams params) {
  forEachReconfigurable(config, params, [](const auto& field, auto& value) { value = field; });
  return params;
}

}  // namespace risas_ros

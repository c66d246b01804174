#pragma once
/// @file similarity_conformance.hpp
/// Conformance checks for similarity plugins (header-only, Catch2 v2). A plugin's test calls
/// `check_similarity_conformance(plugin, samples)` with a few token sequences of its domain; the
/// kit adds empty and unknown-word sequences and checks, for every pair:
/// - the value is finite and in [-1, 1] (never NaN, also for empty and unknown inputs);
/// - symmetry: sim(a, b) == sim(b, a) (within 1e-9);
/// - identity dominates: sim(a, a) >= sim(a, b) for every b (within 1e-9);
/// - determinism: the same call gives the same value.

#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "flipper/sdk/similarity.hpp"

namespace flipper::testing {

inline void check_similarity_conformance(const sdk::Similarity& sim,
                                         std::vector<std::vector<std::string>> samples) {
  samples.push_back({});
  samples.push_back({"qzxvbnmw"});
  samples.push_back({"qzxvbnmw", "wplkjhgq"});
  samples.push_back({""});
  for (const auto& a : samples) {
    const double self = sim.similarity(a, a);
    for (const auto& b : samples) {
      INFO("a = " << Catch::Detail::stringify(a) << ", b = " << Catch::Detail::stringify(b));
      const double ab = sim.similarity(a, b);
      const double ba = sim.similarity(b, a);
      REQUIRE(std::isfinite(ab));
      CHECK(ab >= -1.0);
      CHECK(ab <= 1.0);
      CHECK(std::abs(ab - ba) <= 1e-9);
      CHECK(self >= ab - 1e-9);
      CHECK(sim.similarity(a, b) == ab);
    }
  }
  // Unknown and empty inputs know nothing: 0.
  INFO("similarity({}, {}) and similarity({qzxvbnmw}, {wplkjhgq}): want 0");
  CHECK(sim.similarity({}, {}) == 0.0);
  CHECK(sim.similarity({"qzxvbnmw"}, {"wplkjhgq"}) == 0.0);
}

}  // namespace flipper::testing

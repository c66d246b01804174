#pragma once
/// @file core_scorer.hpp
/// A scorer for testing parsers (header-only): every node scores the core bonus of
/// docs/naturalization.md §3 alone (1.0 when its subtree uses only core rules, else 0), which is
/// what every scorer gives before it learns; it has no features, learns nothing and has no state.
/// The parser kit's driver parses with it (cmake/flipper_parser_conformance.cpp); a test may
/// derive from it to score otherwise.

#include <string>
#include <string_view>
#include <vector>

#include "flipper/sdk/scorer.hpp"

namespace flipper::testing {

class CoreScorer : public sdk::Scorer {
 protected:
  double do_score_node(const sdk::Derivation& node, const sdk::ScoreContext&) const override {
    return node.core_only ? 1.0 : 0.0;
  }
  void do_features(const sdk::Derivation&, const sdk::ScoreContext&,
                   sdk::FeatureVector&) const override {}
  void do_learn(const std::vector<sdk::Candidate>&, std::size_t,
                const sdk::ScoreContext&) override {}
  std::string do_save_state() const override { return {}; }
  void do_load_state(std::string_view) override {}
};

}  // namespace flipper::testing

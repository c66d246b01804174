#pragma once
/// @file scorer_conformance.hpp
/// Conformance checks for scorer plugins (header-only, Catch2 v2). A plugin's test gives a fresh
/// scorer and a parser with the core grammar and one ambiguous utterance (>= 2 candidates); it
/// checks that
/// - every node's local score is finite, and a fresh scorer gives a core-only node 1.0 or more;
/// - features() is deterministic;
/// - learning on an accept moves the accepted candidate's score up relative to the others
///   (the accepted, initially not top, candidate rises above the former top after a few accepts);
/// - save_state/load_state round-trips: a second instance loaded from the state scores every
///   node exactly as the first; unreadable state throws Error(bad_config);
/// - a scorer with sdk::StateWeights reads its saved state as weights that pass the host's check
///   (sdk::state_weights_violation) and, with sdk::IncrementalScorer, added to a fresh instance
///   score every node exactly as the scorer that saved it; it reads no state in other text.

#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "flipper/sdk/answer_check.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/scorer.hpp"

namespace flipper::testing {

inline void for_each_node(const sdk::Derivation& d,
                          const std::function<void(const sdk::Derivation&)>& f) {
  f(d);
  for (const auto& k : d.kids) for_each_node(*k, f);
}

/// `fresh` makes a new scorer instance (default parameters).
inline void check_scorer_conformance(const std::function<std::shared_ptr<sdk::Scorer>()>& fresh,
                                     const sdk::Parser& parser, const std::string& ambiguous) {
  auto scorer = fresh();
  sdk::ParseRequest req;
  req.tokens = sdk::tokenize(ambiguous);
  req.context.user = "alice";
  req.scorer = scorer.get();
  INFO("the ambiguous utterance: " << ambiguous);
  auto r = parser.parse(req);
  INFO("parsed into " << r.candidates.size() << " candidates; the kit needs at least 2");
  REQUIRE(r.candidates.size() >= 2);
  sdk::ScoreContext ctx = req.context;
  ctx.tokens = &req.tokens;
  for (const auto& c : r.candidates)
    for (const auto& d : c.derivations)
      for_each_node(*d, [&](const sdk::Derivation& n) {
        const double s = scorer->score_node(n, ctx);
        INFO("candidate " << sdk::render(c.program) << ", node " << n.category() << " over tokens ["
                          << n.start << ", " << n.end << ") by rule " << n.rule->id << " ("
                          << (n.core_only ? "core" : "induced") << "): score " << s);
        CHECK(std::isfinite(s));
        if (n.core_only) CHECK(s >= 1.0);
        sdk::FeatureVector f1, f2;
        scorer->features(n, ctx, f1);
        scorer->features(n, ctx, f2);
        CHECK(f1 == f2);
      });
  // Learning: accept the last candidate until it is on top (at most 10 accepts).
  const sdk::Program wanted = r.candidates.back().program;
  bool on_top = false;
  for (int round = 0; round < 10 && !on_top; ++round) {
    std::size_t idx = 0;
    for (std::size_t i = 0; i < r.candidates.size(); ++i)
      if (sdk::equal(r.candidates[i].program, wanted)) idx = i;
    scorer->learn(r.candidates, idx, ctx);
    r = parser.parse(req);
    on_top = sdk::equal(r.candidates.front().program, wanted);
  }
  INFO("accepted " << sdk::render(wanted) << " up to 10 times; the top is now "
                   << sdk::render(r.candidates.front().program));
  CHECK(on_top);
  // Persistence.
  const std::string state = scorer->save_state();
  auto other = fresh();
  REQUIRE_NOTHROW(other->load_state(state));
  for (const auto& c : r.candidates)
    for (const auto& d : c.derivations)
      for_each_node(*d, [&](const sdk::Derivation& n) {
        INFO("after save_state/load_state: candidate "
             << sdk::render(c.program) << ", node " << n.category() << " over tokens [" << n.start
             << ", " << n.end << ")");
        CHECK(other->score_node(n, ctx) == scorer->score_node(n, ctx));
      });
  INFO("load_state(\"not a state {\"): want sdk::Error(bad_config)");
  CHECK_THROWS_AS(other->load_state("not a state {"), sdk::Error);
  // The saved state as weights (SDK 3.1).
  const auto* reader = dynamic_cast<const sdk::StateWeights*>(scorer.get());
  if (reader == nullptr) return;
  CHECK_FALSE(reader->state_weights("not a state {").has_value());
  const auto weights = reader->state_weights(state);
  INFO("state_weights(save_state()): want the weights, not nullopt");
  REQUIRE(weights.has_value());
  const auto violation = sdk::state_weights_violation(state.size(), *weights);
  INFO("state_weights(save_state()) breaks the host's check: " << violation.value_or(""));
  CHECK_FALSE(violation.has_value());
  auto added = fresh();
  auto* inc = dynamic_cast<sdk::IncrementalScorer*>(added.get());
  if (inc == nullptr) return;
  inc->apply_changes(*weights);
  inc->commit_changes();
  for (const auto& c : r.candidates)
    for (const auto& d : c.derivations)
      for_each_node(*d, [&](const sdk::Derivation& n) {
        INFO("state_weights(save_state()) added to a fresh scorer: candidate "
             << sdk::render(c.program) << ", node " << n.category() << " over tokens [" << n.start
             << ", " << n.end << ")");
        CHECK(added->score_node(n, ctx) == scorer->score_node(n, ctx));
      });
}

}  // namespace flipper::testing

#pragma once
/// @file generalizer.hpp
/// Generalization by rewriting (naturalization.md §6): asks the rewriter plugin for alternative
/// bodies, keeps those equivalent to the user's body in the world where the definition was made
/// (same trace and final world, run from the world before the first body line; optionally also on
/// perturbed copies of that world), and selects the best by
/// σ = (best-packing score against the head chart, similarity(head, candidate), generality).

#include <functional>
#include <string>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/rewriter.hpp"
#include "flipper/sdk/similarity.hpp"

namespace flipper::kernel {

struct GeneralizeCandidate {
  sdk::Program program;
  std::string rewriting;        ///< from the rewriter; "body" for the user's own body
  bool equivalent = false;      ///< passed every equivalence check
  std::string rejected_reason;  ///< why it was discarded (empty when kept)
  double packing_score = 0;
  double similarity = 0;
  int generality = 0;           ///< minus the number of nodes
};

struct GeneralizeResult {
  sdk::Program winner;            ///< the body to induce from (the user's body if nothing beats it)
  bool body_won = true;
  std::string winner_rewriting;   ///< empty when the body won
  std::vector<GeneralizeCandidate> candidates;  ///< the body first, then generation order
};

struct GeneralizeOptions {
  int perturbed_checks = 0;  ///< extra equivalence checks on perturbed copies of the world
};

class Generalizer {
 public:
  Generalizer(const sdk::Rewriter& rewriter, const sdk::Similarity* similarity,
              const sdk::ExecutionService& exec, GeneralizeOptions options = {});
  /// @param packing_score best-packing score of a program against the head chart (inducer).
  GeneralizeResult generalize(const std::vector<std::string>& head_tokens,
                              const sdk::Program& body, const sdk::WorldState& before,
                              const std::function<double(const sdk::Program&)>& packing_score) const;

 private:
  const sdk::Rewriter& rewriter_;
  const sdk::Similarity* similarity_;
  const sdk::ExecutionService& exec_;
  GeneralizeOptions options_;
};

}  // namespace flipper::kernel

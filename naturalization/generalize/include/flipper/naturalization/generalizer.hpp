#pragma once
/// @file generalizer.hpp
/// Generalization by rewriting (docs/naturalization.md §6): asks the rewriter plugin for
/// alternative bodies, keeps those equivalent to the user's body in the world where the definition
/// was made (same trace and final world, run from the world before the first body line; optionally
/// also on perturbed copies of that world), and selects the best by σ = (best-packing score against
/// the head chart, similarity(head, candidate), generality).
///
/// Perturbed checks (beyond the original, off by default): with `perturbed_checks = n > 0`, the
/// body and each candidate also run on n seeded perturbations of the world (robot elsewhere,
/// items moved). A candidate that differs there stays eligible — a generalization is *meant* to
/// behave differently in other worlds, and the packing score is what says the head asks for it —
/// but σ gains a component: σ = (packing, similarity, perturbations passed, generality). So among
/// candidates that read equally well, the one that agrees with the body on more perturbed worlds
/// wins before the shorter one does. Failed perturbations are listed per candidate.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/rewriter.hpp"
#include "flipper/sdk/similarity.hpp"

namespace flipper::naturalization {

struct GeneralizeCandidate {
  sdk::Program program;
  std::string rewriting;        ///< from the rewriter; "body" for the user's own body
  bool equivalent = false;      ///< equivalent to the body in the world of the definition
                                ///< (the body: false only when it raised an execution error)
  std::string rejected_reason;  ///< why it was discarded (empty when kept; always for the body)
  double packing_score = 0;
  double similarity = 0;
  int generality = 0;                      ///< minus the number of nodes
  int perturbed_passed = 0;                ///< perturbed worlds on which it agrees with the body
  std::vector<std::string> failed_checks;  ///< e.g. "perturbation 2: different trace at step 1"
};

struct GeneralizeResult {
  sdk::Program winner;  ///< the body to induce from (the user's body if nothing beats it)
  bool body_won = true;
  std::string winner_rewriting;  ///< empty when the body won
  std::size_t winner_index = 0;  ///< index of the winner in `candidates` (0: the body)
  std::vector<GeneralizeCandidate> candidates;  ///< the body first, then generation order
  int perturbations = 0;  ///< perturbed worlds actually used (body ran without error)
};

struct GeneralizeOptions {
  int perturbed_checks = 0;  ///< extra equivalence checks on perturbed copies of the world
  std::uint64_t perturbation_seed = 20180917;  ///< seed of the perturbations (deterministic)
};

class Generalizer {
 public:
  /// `similarity` may be empty (no similarity feature). Calls go through the refs.
  Generalizer(kernel::PluginRef<const sdk::Rewriter> rewriter,
              kernel::PluginRef<const sdk::Similarity> similarity,
              const sdk::ExecutionService& exec, GeneralizeOptions options = {});
  /// @param head_tokens the head's tokens (lexed, lower case).
  /// @param packing_score best-packing score of a program against the head chart (inducer); an
  ///        empty function scores every program 0.
  /// Throws sdk::Error(plugin_error, naming the plugin) when the rewriter or the similarity
  /// plugin fails; an sdk::Error they throw keeps its code.
  GeneralizeResult generalize(
      const std::vector<std::string>& head_tokens, const sdk::Program& body,
      const sdk::WorldState& before,
      const std::function<double(const sdk::Program&)>& packing_score) const;

 private:
  kernel::PluginRef<const sdk::Rewriter> rewriter_;
  kernel::PluginRef<const sdk::Similarity> similarity_;
  const sdk::ExecutionService& exec_;
  GeneralizeOptions options_;
};

/// `count` perturbed copies of `world` (robot elsewhere, items moved), the same for the same seed:
/// the worlds the perturbed checks use (docs/naturalization.md §6). Empty when the world has fewer
/// than two free cells.
std::vector<sdk::WorldState> perturbed_worlds(
    const sdk::WorldState& world, int count,
    std::uint64_t seed = GeneralizeOptions{}.perturbation_seed);

/// Words of the head for the similarity: its tokens without `, [ ] { }` (docs/naturalization.md
/// §6).
std::vector<std::string> head_words(const std::vector<std::string>& head_tokens);
/// Words of a candidate: its canonical text's tokens without `{ } [ ] , ;` and the words
/// `is containing in item items and`.
std::vector<std::string> candidate_words(const sdk::Program& program);

}  // namespace flipper::naturalization

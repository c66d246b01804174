#pragma once
/// @file scorer.hpp
/// Scorer plugins: the ranking model (docs/naturalization.md §3). The parser asks for each new
/// derivation node's local score while it builds the chart; the kernel asks the scorer to learn
/// when the user accepts a candidate, and to save/restore its state with the lexicon.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "flipper/sdk/derivation.hpp"
#include "flipper/sdk/export.hpp"
#include "flipper/sdk/plugin.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// Sparse features: (name, value).
using FeatureVector = std::vector<std::pair<std::string, double>>;

/// What a score may depend on besides the derivation itself.
/// How often the candidates built with an induced rule were accepted, by the rule's author and
/// by everyone else.
struct RuleUses {
  std::uint64_t by_author = 0;
  std::uint64_t by_others = 0;
  friend bool operator==(const RuleUses&, const RuleUses&) = default;
};

/// The kernel's use counters, read-only to plugins. Thread-safe.
class FLIPPER_SDK_API UsageCounters {
 public:
  virtual ~UsageCounters();
  /// Zero for a rule never used (or unknown).
  virtual RuleUses uses(const std::string& rule_id) const = 0;
};

struct ScoreContext {
  const std::vector<std::string>* tokens = nullptr;  ///< the utterance's tokens
  std::string user;                                  ///< the current user
  const UsageCounters* usage = nullptr;  ///< the kernel's use counters; null: nothing used yet
};

class FLIPPER_SDK_API Scorer : public Plugin {
 public:
  using Interface = Scorer;
  ~Scorer() override;

  /// Local score of `node` (its kids are complete): w·φ(node), plus 1.0 when the node's subtree
  /// uses only core rules. The node's total is this plus its kids' totals (the parser adds).
  /// Must be cheap and thread-compatible (const, no mutation).
  double score_node(const Derivation& node, const ScoreContext& ctx) const {
    return do_score_node(node, ctx);
  }
  /// Features of one node (not its kids), for inspection and tests.
  void features(const Derivation& node, const ScoreContext& ctx, FeatureVector& out) const {
    do_features(node, ctx, out);
  }
  /// Learns from an accept: `candidates` as returned for the query (all of them, every
  /// derivation), `accepted` indexes the chosen one.
  void learn(const std::vector<Candidate>& candidates, std::size_t accepted,
             const ScoreContext& ctx) {
    do_learn(candidates, accepted, ctx);
  }
  /// Serialised model state (weights, AdaGrad sums) for persistence; opaque text.
  std::string save_state() const { return do_save_state(); }
  /// Restores a state produced by save_state(); throws Error(bad_config) if unreadable.
  void load_state(std::string_view state) { do_load_state(state); }

 protected:
  virtual double do_score_node(const Derivation& node, const ScoreContext& ctx) const = 0;
  virtual void do_features(const Derivation& node, const ScoreContext& ctx,
                           FeatureVector& out) const = 0;
  virtual void do_learn(const std::vector<Candidate>& candidates, std::size_t accepted,
                        const ScoreContext& ctx) = 0;
  virtual std::string do_save_state() const = 0;
  virtual void do_load_state(std::string_view state) = 0;
};

/// One weight's change, additive: applying a change to any state adds `weight` to the
/// weight and `aux` to its per-weight learning statistic (e.g. AdaGrad's sum of squared
/// gradients; 0 when the model has none). `model` is the scorer's own partition ("" for one global
/// model, the user for a scorer with per-user weights), `feature` the weight's stable name.
struct WeightChange {
  std::string model;
  std::string feature;
  double weight = 0;
  double aux = 0;
};

/// Optional extension of a Scorer, found with dynamic_cast: a scorer that reports what
/// each learn() changed lets the kernel persist only the changed weights, as deltas that add up
/// when several processes learn on one lexicon (docs/naturalization.md §5), instead of the whole
/// state with save_state() (last writer wins). A scorer without it keeps working as before.
///
/// Protocol: learn() records changes as pending; the kernel reads pending_changes(), persists them
/// and calls commit_changes(), or discard_changes() when the accept is undone, which restores the
/// exact state from before those learn() calls. apply_changes() adds stored changes (this and
/// other processes') to the state, e.g. after load_state() at start-up.
class FLIPPER_SDK_API IncrementalScorer {
 public:
  virtual ~IncrementalScorer();
  std::vector<WeightChange> pending_changes() const { return do_pending_changes(); }
  void commit_changes() { do_commit_changes(); }
  void discard_changes() { do_discard_changes(); }
  void apply_changes(const std::vector<WeightChange>& changes) { do_apply_changes(changes); }

 protected:
  virtual std::vector<WeightChange> do_pending_changes() const = 0;
  virtual void do_commit_changes() = 0;
  virtual void do_discard_changes() = 0;
  virtual void do_apply_changes(const std::vector<WeightChange>& changes) = 0;
};

/// Optional extension of an IncrementalScorer, found with dynamic_cast: the pending weights as
/// values, not changes, for a host that runs learn() in a child process (the kernel's
/// plugins.isolation, docs/plugins-untrusted.md §6). A change added to the parent's weight may
/// differ from the child's weight in the last bit (w + (w' - w) need not be w'); a value set is
/// exactly the child's. A WeightChange here holds a weight's value and its aux, not a change.
class FLIPPER_SDK_API WeightValues {
 public:
  virtual ~WeightValues();
  /// The value now of every weight changed since the last commit (one that came back to its
  /// value before too), in any order.
  std::vector<WeightChange> pending_values() const { return do_pending_values(); }
  /// Sets each named weight to its value, as learn() changes it: pending, its value before kept,
  /// so that pending_changes() and discard_changes() work as after the learn() that made them.
  void set_values(const std::vector<WeightChange>& values) { do_set_values(values); }

 protected:
  virtual std::vector<WeightChange> do_pending_values() const = 0;
  virtual void do_set_values(const std::vector<WeightChange>& values) = 0;
};

/// Optional extension of a Scorer, found with dynamic_cast (SDK 3.1): reads a state that
/// save_state() wrote as weights, so that a host can move a saved state into stored weights
/// without knowing its format, which stays the scorer's own (docs/naturalization.md §5 "Learned
/// state": an older store's per-user states are folded into the one weights key). A scorer
/// without it keeps working; a host then keeps such states as they are.
class FLIPPER_SDK_API StateWeights {
 public:
  virtual ~StateWeights();
  /// The weights a state saved by save_state() holds, as values (a WeightChange here holds a
  /// weight's value and its aux, `model` its partition): applied as changes to a scorer whose
  /// weights are all 0 they give the weights load_state(saved_state) gives. nullopt when the
  /// text is no state of this scorer. Does not change the scorer. The host checks the answer
  /// (sdk::state_weights_violation): every number finite, at most one weight per byte of text.
  std::optional<std::vector<WeightChange>> state_weights(std::string_view saved_state) const {
    return do_state_weights(saved_state);
  }

 protected:
  virtual std::optional<std::vector<WeightChange>> do_state_weights(
      std::string_view saved_state) const = 0;
};

template <>
struct KindOf<Scorer> {
  static constexpr PluginKind value = PluginKind::scorer;
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk

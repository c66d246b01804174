#pragma once
/// @file linear_model.hpp
/// A sparse linear ranking model over the node features of docs/naturalization.md §3
/// (features.hpp): the score, one weight vector per partition (one global vector, or one per
/// user), the bookkeeping of sdk::IncrementalScorer (changes pending since the last commit, their
/// undo, stored changes added in) and the saved state. A scorer plugin keeps only its update rule:
/// `loglinear` (AdaGrad + L1) and `perceptron` (averaged perceptron) are built on it.
///
/// Each weight carries a second number, `aux`, its learning statistic (AdaGrad's sum of squared
/// gradients, the perceptron's sum for averaging): sdk::WeightChange adds to both, so several
/// processes learning on one lexicon keep every update (docs/naturalization.md §5).
/// Besides weights a partition may count the accepts it learnt from (count_accept), persisted
/// the same way as the change of a reserved feature, kAcceptsFeature.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "flipper/sdk/scorer.hpp"
#include "flipper/toolkit/features.hpp"

namespace flipper::toolkit {

struct LinearWeight {
  double w = 0;
  double aux = 0;  ///< the update rule's statistic for this weight
};

/// One weight vector: weights by feature key (features::feature_key of the name), and the names.
struct LinearPartition {
  std::unordered_map<std::uint64_t, LinearWeight> weights;
  features::FeatureNames names;
  /// The weight of `key`, null when it was never changed.
  const LinearWeight* find(std::uint64_t key) const {
    auto it = weights.find(key);
    return it == weights.end() ? nullptr : &it->second;
  }
};

/// The reserved feature name under which count_accept() keeps a partition's accepts (no feature
/// of features.hpp starts with '#').
inline constexpr std::string_view kAcceptsFeature = "#accepts";

/// How a model's saved state is written: `format` names it (and must match on load), `plugin`
/// prefixes error messages. With `counter` set, each partition is written as
/// {counter: 1 + accepts, "weights": {...}}, else as the weights object alone (partitions without
/// weights are then left out).
struct LinearStateFormat {
  std::string_view plugin;
  std::string_view format;
  std::string_view counter;
};

class LinearModel {
 public:
  /// `per_user`: one partition per user (ScoreContext::user), else one global partition ("").
  explicit LinearModel(bool per_user) : per_user_(per_user) {}

  bool per_user() const { return per_user_; }
  /// The partition a context scores with and learns into: "" or the user.
  std::string partition_name(const sdk::ScoreContext& ctx) const {
    return per_user_ ? ctx.user : std::string();
  }
  /// The context's partition, null when it never learnt anything.
  const LinearPartition* find(const sdk::ScoreContext& ctx) const;
  /// The context's partition, created when missing (for learning).
  LinearPartition& partition(const sdk::ScoreContext& ctx);

  /// The score of docs/naturalization.md §3: 1.0 for a core-only node, plus value(w)·φ(node)
  /// summed in feature order, where value(const LinearWeight&) -> double reads a weight (its w,
  /// or an average).
  template <class Value>
  double score_node(const sdk::Derivation& node, const sdk::ScoreContext& ctx,
                    Value&& value) const {
    const double core = node.core_only ? 1.0 : 0.0;
    const LinearPartition* m = find(ctx);
    if (m == nullptr || m->weights.empty()) return core;
    return features::weighted_sum(core, node, ctx, [&](std::uint64_t key) {
      const LinearWeight* w = m->find(key);
      return w == nullptr ? 0.0 : value(*w);
    });
  }
  /// The features of one node (Scorer::features).
  static void node_features(const sdk::Derivation& node, const sdk::ScoreContext& ctx,
                            sdk::FeatureVector& out) {
    features::node_features(node, ctx, out);
  }
  /// Adds coef·φ(d), φ summed over every node of the tree, to `out`, and names the features in
  /// the context's partition (so changes to them can be persisted by name).
  void add_tree_features(const sdk::Derivation& d, const sdk::ScoreContext& ctx, double coef,
                         features::SparseVector& out);

  /// The weight `key` of the context's partition for an update (created at 0 when missing); its
  /// value before the first change since the last commit is kept, for pending_changes() and
  /// discard_changes(). The feature must have been named (add_tree_features).
  LinearWeight& change(const sdk::ScoreContext& ctx, std::uint64_t key);
  /// Counts one accept in the context's partition (a pending change like any other).
  void count_accept(const sdk::ScoreContext& ctx);
  /// The accepts counted in `m`.
  static double accepts(const LinearPartition& m);

  // sdk::IncrementalScorer: a scorer plugin forwards these four.
  std::vector<sdk::WeightChange> pending_changes() const;
  void commit_changes() { pending_.clear(); }
  void discard_changes();
  void apply_changes(const std::vector<sdk::WeightChange>& changes);
  // sdk::WeightValues: the same, as values (a plugin run in a child process sends them).
  std::vector<sdk::WeightChange> pending_values() const;
  void set_values(const std::vector<sdk::WeightChange>& values);

  /// The whole state (Scorer::save_state), partitions and weights by name.
  std::string save_state(const LinearStateFormat& format) const;
  /// Replaces the state with a saved one; Error(bad_config) naming the plugin when the text is
  /// not such a state (and then nothing changes). Pending changes are dropped.
  void load_state(std::string_view state, const LinearStateFormat& format);
  /// The weights a saved state holds, as values (sdk::StateWeights): exactly what load_state
  /// loads, each partition's accepts as the weight kAcceptsFeature first (a counted layout's
  /// counter c > 1 is c - 1 accepts), then its weights in name order. nullopt when load_state
  /// would refuse the text.
  static std::optional<std::vector<sdk::WeightChange>> state_weights(
      std::string_view state, const LinearStateFormat& format);

 private:
  LinearWeight& change(std::string partition, std::uint64_t key);

  struct PendingKey {
    std::string partition;
    std::uint64_t key;
    bool operator<(const PendingKey& o) const {
      return key != o.key ? key < o.key : partition < o.partition;
    }
  };
  struct Before {
    LinearWeight value;
    bool existed = false;
  };

  bool per_user_;
  std::unordered_map<std::string, LinearPartition> partitions_;  // key: user ("" when global)
  std::map<PendingKey, Before> pending_;  // weights changed since the last commit, values before
};

}  // namespace flipper::toolkit

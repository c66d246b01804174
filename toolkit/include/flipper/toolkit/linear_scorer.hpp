#pragma once
/// @file linear_scorer.hpp
/// A scorer plugin over the toolkit's LinearModel (linear_model.hpp): features, scores, per-user
/// partitions, saved state, sdk::IncrementalScorer, sdk::WeightValues and sdk::StateWeights are
/// done here; a plugin derives from it and writes its update rule (`update`) and, when it scores
/// with something else than the weights themselves (e.g. their average), `do_score_node`.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/sdk/scorer.hpp"
#include "flipper/toolkit/linear_model.hpp"

namespace flipper::toolkit {

class LinearScorer : public sdk::Scorer,
                     public sdk::IncrementalScorer,
                     public sdk::WeightValues,
                     public sdk::StateWeights {
 protected:
  LinearScorer(bool per_user, LinearStateFormat format) : format_(format), model_(per_user) {}

  /// Learns from an accept; `accepted` indexes `candidates` (checked before).
  virtual void update(const std::vector<sdk::Candidate>& candidates, std::size_t accepted,
                      const sdk::ScoreContext& ctx) = 0;

  LinearModel& model() { return model_; }
  const LinearModel& model() const { return model_; }

  /// The weights as they are: w·φ(node) plus the core bonus.
  double do_score_node(const sdk::Derivation& node, const sdk::ScoreContext& ctx) const override;
  void do_features(const sdk::Derivation& node, const sdk::ScoreContext& ctx,
                   sdk::FeatureVector& out) const override;
  /// Error(bad_request) for an index out of range, then update().
  void do_learn(const std::vector<sdk::Candidate>& candidates, std::size_t accepted,
                const sdk::ScoreContext& ctx) final;
  std::string do_save_state() const override;
  void do_load_state(std::string_view state) override;

  std::vector<sdk::WeightChange> do_pending_changes() const override;
  void do_commit_changes() override;
  void do_discard_changes() override;
  void do_apply_changes(const std::vector<sdk::WeightChange>& changes) override;
  std::vector<sdk::WeightChange> do_pending_values() const override;
  void do_set_values(const std::vector<sdk::WeightChange>& values) override;
  std::optional<std::vector<sdk::WeightChange>> do_state_weights(
      std::string_view saved_state) const override;

 private:
  const LinearStateFormat format_;
  LinearModel model_;
};

}  // namespace flipper::toolkit

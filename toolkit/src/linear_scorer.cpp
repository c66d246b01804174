#include "flipper/toolkit/linear_scorer.hpp"

#include "flipper/sdk/errors.hpp"

namespace flipper::toolkit {

double LinearScorer::do_score_node(const sdk::Derivation& node,
                                   const sdk::ScoreContext& ctx) const {
  return model_.score_node(node, ctx, [](const LinearWeight& w) { return w.w; });
}

void LinearScorer::do_features(const sdk::Derivation& node, const sdk::ScoreContext& ctx,
                               sdk::FeatureVector& out) const {
  LinearModel::node_features(node, ctx, out);
}

void LinearScorer::do_learn(const std::vector<sdk::Candidate>& candidates, std::size_t accepted,
                            const sdk::ScoreContext& ctx) {
  if (accepted >= candidates.size())
    throw sdk::Error(sdk::codes::kBadRequest,
                     std::string(format_.plugin) + ": accepted index " + std::to_string(accepted) +
                         " out of range (" + std::to_string(candidates.size()) + " candidates)");
  update(candidates, accepted, ctx);
}

std::string LinearScorer::do_save_state() const {
  return model_.save_state(format_);
}
void LinearScorer::do_load_state(std::string_view state) {
  model_.load_state(state, format_);
}

std::vector<sdk::WeightChange> LinearScorer::do_pending_changes() const {
  return model_.pending_changes();
}
void LinearScorer::do_commit_changes() {
  model_.commit_changes();
}
void LinearScorer::do_discard_changes() {
  model_.discard_changes();
}
void LinearScorer::do_apply_changes(const std::vector<sdk::WeightChange>& changes) {
  model_.apply_changes(changes);
}
std::vector<sdk::WeightChange> LinearScorer::do_pending_values() const {
  return model_.pending_values();
}
void LinearScorer::do_set_values(const std::vector<sdk::WeightChange>& values) {
  model_.set_values(values);
}
std::optional<std::vector<sdk::WeightChange>> LinearScorer::do_state_weights(
    std::string_view saved_state) const {
  return LinearModel::state_weights(saved_state, format_);
}

}  // namespace flipper::toolkit

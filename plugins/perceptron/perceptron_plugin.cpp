// The `perceptron` scorer: an averaged structured perceptron on the toolkit's linear model
// (flipper/toolkit/linear_scorer.hpp: the features of docs/naturalization.md §3, per-user
// weights, incremental persistence, so two processes learning on one lexicon keep both updates).
//
// On an accept, the model's prediction is the highest-scoring derivation of the query (scores as
// computed at parse time; ties: the first in candidate order). If it yields the accepted program,
// nothing changes; otherwise w += rate · (φ(accepted) − φ(predicted)), with φ summed over every
// node of the accepted program's best derivation and of the predicted derivation. Scores use the
// averaged weights w − u/c (Daumé's lazy averaging: u += c · Δ on every update, kept as each
// weight's aux; c = 1 + the accepts learnt from, counted by the model), i.e. the mean of the
// weight vectors after every accept.
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/toolkit/linear_scorer.hpp"

namespace flipper::plugins::perceptron {

namespace {

namespace param = sdk::param;

constexpr param::Double kRate{"rate", 1.0, 0.0, 100.0, "size of a perceptron update"};
constexpr param::Bool kPerUser{"per_user", false,
                               "keep one weight vector per user instead of a global one"};

// The accepted program's highest-scoring derivation (the first of equals).
const sdk::Derivation* best_derivation(const sdk::Candidate& c) {
  const sdk::Derivation* best = nullptr;
  for (const auto& d : c.derivations)
    if (best == nullptr || d->score > best->score) best = d.get();
  return best;
}

}  // namespace

class Perceptron : public toolkit::LinearScorer {
 public:
  explicit Perceptron(const sdk::Params& p)
      : LinearScorer(param::get(p, kPerUser), {"perceptron", "flipper.perceptron/1", "c"}),
        rate_(param::get(p, kRate)) {}

  static sdk::ParamSchema schema() { return param::schema(kRate, kPerUser); }

 protected:
  double do_score_node(const sdk::Derivation& node, const sdk::ScoreContext& ctx) const override {
    const toolkit::LinearPartition* m = model().find(ctx);
    const double c = 1 + (m == nullptr ? 0.0 : toolkit::LinearModel::accepts(*m));
    return model().score_node(node, ctx,
                              [c](const toolkit::LinearWeight& w) { return w.w - w.aux / c; });
  }

  void update(const std::vector<sdk::Candidate>& candidates, std::size_t accepted,
              const sdk::ScoreContext& ctx) override {
    const sdk::Candidate& gold = candidates[accepted];
    if (gold.derivations.empty()) return;
    const sdk::Derivation* predicted = nullptr;
    bool predicted_is_gold = false;
    for (std::size_t ci = 0; ci < candidates.size(); ++ci)
      for (const auto& d : candidates[ci].derivations)
        if (predicted == nullptr || d->score > predicted->score) {
          predicted = d.get();
          predicted_is_gold = ci == accepted;
        }
    const toolkit::LinearPartition& m = model().partition(ctx);
    const double c = 1 + toolkit::LinearModel::accepts(m);
    if (predicted != nullptr && !predicted_is_gold && !sdk::equal(predicted->sem, gold.program)) {
      toolkit::features::SparseVector delta;
      model().add_tree_features(*best_derivation(gold), ctx, rate_, delta);
      model().add_tree_features(*predicted, ctx, -rate_, delta);
      for (const auto& [key, d] : delta) {
        if (d == 0) continue;
        toolkit::LinearWeight& w = model().change(ctx, key);
        w.w += d;
        w.aux += c * d;
      }
    }
    model().count_accept(ctx);
  }

 private:
  const double rate_;
};

}  // namespace flipper::plugins::perceptron

FLIPPER_PLUGIN(flipper::plugins::perceptron::Perceptron, scorer, "perceptron",
               FLIPPER_PLUGIN_VERSION, "Averaged structured perceptron over the loglinear features")

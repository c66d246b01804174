// The `loglinear` scorer: AdaGrad + L1 learning on accept, marginalised over the derivations of
// the accepted program (docs/naturalization.md §3), on the toolkit's linear model (features,
// per-user weights, incremental persistence: flipper/toolkit/linear_scorer.hpp).
#include <cmath>
#include <limits>

#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/toolkit/linear_scorer.hpp"

namespace flipper::plugins::loglinear {

namespace {

namespace param = sdk::param;

constexpr param::Double kStep{"step", 0.1, 0.0, 100.0, "AdaGrad step size"};
constexpr param::Double kL1{"l1", 1e-4, 0.0, 1.0,
                            "L1 regularisation strength (scaled by the AdaGrad step)"};
constexpr param::Bool kPerUser{"per_user", false,
                               "keep one weight vector per user instead of a global one"};

}  // namespace

class LogLinear : public toolkit::LinearScorer {
 public:
  explicit LogLinear(const sdk::Params& p)
      : LinearScorer(param::get(p, kPerUser), {"loglinear", "flipper.loglinear/1", ""}),
        step_(param::get(p, kStep)),
        l1_(param::get(p, kL1)) {}

  static sdk::ParamSchema schema() { return param::schema(kStep, kL1, kPerUser); }

 protected:
  // Softmax over every derivation of every candidate (model) and over the accepted program's
  // derivations only (target); scores as computed at parse time. Each weight's aux is AdaGrad's
  // sum of squared gradients.
  void update(const std::vector<sdk::Candidate>& candidates, std::size_t accepted,
              const sdk::ScoreContext& ctx) override {
    double max_score = -std::numeric_limits<double>::infinity();
    for (const auto& c : candidates)
      for (const auto& d : c.derivations) max_score = std::max(max_score, d->score);
    if (!std::isfinite(max_score)) return;
    double z_model = 0, z_target = 0;
    for (std::size_t ci = 0; ci < candidates.size(); ++ci)
      for (const auto& d : candidates[ci].derivations) {
        const double e = std::exp(d->score - max_score);
        z_model += e;
        if (ci == accepted) z_target += e;
      }
    if (z_target <= 0) return;
    toolkit::features::SparseVector grad;
    for (std::size_t ci = 0; ci < candidates.size(); ++ci)
      for (const auto& d : candidates[ci].derivations) {
        const double e = std::exp(d->score - max_score);
        const double coef = (ci == accepted ? e / z_target : 0.0) - e / z_model;
        if (coef == 0) continue;
        model().add_tree_features(*d, ctx, coef, grad);
      }
    for (const auto& [key, g] : grad) {
      if (g == 0) continue;
      toolkit::LinearWeight& w = model().change(ctx, key);
      w.aux += g * g;
      const double rate = step_ / std::sqrt(w.aux + 1.0);
      w.w += rate * g;
      const double shrink = rate * l1_;
      w.w = w.w > 0 ? std::max(0.0, w.w - shrink) : std::min(0.0, w.w + shrink);
    }
  }

 private:
  const double step_;
  const double l1_;
};

}  // namespace flipper::plugins::loglinear

FLIPPER_PLUGIN(flipper::plugins::loglinear::LogLinear, scorer, "loglinear", FLIPPER_PLUGIN_VERSION,
               "Log-linear ranking model with AdaGrad + L1 learning on accept")

// example_scorer: a linear ranking model on the toolkit's LinearScorer
// (flipper/toolkit/linear_scorer.hpp: the features of docs/naturalization.md §3, scores, per-user
// weights, the saved state and incremental persistence with the lexicon are done there), with its
// own update rule: on an accept, the accepted reading's best derivation gains `rate` on each of
// its features, and the best derivations of the other readings share a loss of `rate`.
#include <flipper/sdk/config_handles.hpp>
#include <flipper/sdk/plugin.hpp>
#include <flipper/toolkit/linear_scorer.hpp>

namespace example_scorer {

namespace sdk = flipper::sdk;
namespace toolkit = flipper::toolkit;
namespace param = flipper::sdk::param;

constexpr param::Double kRate{"rate", 1.0, 0.0, 100.0, "weight moved per accept"};
constexpr param::Bool kPerUser{"per_user", false,
                               "keep one weight vector per user instead of a global one"};

class ExampleScorer : public toolkit::LinearScorer {
 public:
  explicit ExampleScorer(const sdk::Params& p)
      : LinearScorer(param::get(p, kPerUser), {"example_scorer", "example_scorer/1", ""}),
        rate_(param::get(p, kRate)) {}
  static sdk::ParamSchema schema() { return param::schema(kRate, kPerUser); }

 protected:
  void update(const std::vector<sdk::Candidate>& candidates, std::size_t accepted,
              const sdk::ScoreContext& ctx) override {
    const double others = candidates.size() > 1 ? rate_ / double(candidates.size() - 1) : 0.0;
    toolkit::features::SparseVector delta;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const sdk::Derivation* best = nullptr;  // the reading's highest-scoring derivation
      for (const auto& d : candidates[i].derivations)
        if (best == nullptr || d->score > best->score) best = d.get();
      if (best != nullptr)
        model().add_tree_features(*best, ctx, i == accepted ? rate_ : -others, delta);
    }
    // change() records each weight's value before the accept: the kernel stores the changes
    // (and undoes them when the accept does not commit).
    for (const auto& [key, amount] : delta)
      if (amount != 0) model().change(ctx, key).w += amount;
  }

 private:
  const double rate_;
};

}  // namespace example_scorer

FLIPPER_PLUGIN(example_scorer::ExampleScorer, scorer, "example_scorer", FLIPPER_PLUGIN_VERSION,
               "A linear model that moves weight towards the accepted reading")

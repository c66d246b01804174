// evil_scorer: a scorer on the toolkit's linear model (flipper/toolkit/linear_scorer.hpp)
// misbehaving on purpose in learn, for the tests of what the kernel contains
// (docs/plugins-untrusted.md §6). It learns as a perceptron with a step that is not a power of
// two (so that a weight sent as a change would not always come back exactly); in every mode but
// `ok` it misbehaves on an accept whose utterance has the token `on_token` (empty: every accept)
// and learns correctly otherwise:
//   throw   throws std::runtime_error from learn()
//   segv    dereferences a null pointer
//   abort   calls std::abort()
// and one mode that learns correctly but reports its changes wrongly:
//   inexact reports each weight's change rounded to a float (pending_changes), so the changes
//           the kernel stores do not add up to the weights the scorer holds
// Tests select it with --set plugin_paths=[build/tests/plugins/evil] --set
// scorer.plugin=evil_scorer.
#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/toolkit/linear_scorer.hpp"

namespace evil_scorer {
namespace {

namespace sdk = flipper::sdk;
namespace param = flipper::sdk::param;
namespace toolkit = flipper::toolkit;

enum class Mode { ok, throws, segv, abort_, inexact };
constexpr param::Choice<Mode, 5> kMode{
    "mode",
    Mode::ok,
    {"ok", "throw", "segv", "abort", "inexact"},
    "how to misbehave (tests/support/evil_scorer/evil_scorer.cpp)"};
constexpr param::Text kOnToken{"on_token", "",
                               "misbehave only on accepts of utterances with this token (empty: "
                               "every one)"};
constexpr param::Double kRate{"rate", 0.3, 0.0, 100.0, "the perceptron's step"};

class EvilScorer final : public toolkit::LinearScorer {
 public:
  explicit EvilScorer(const sdk::Params& p)
      : LinearScorer(false, {"evil_scorer", "flipper.evil_scorer/1", ""}),
        mode_(param::get(p, kMode)),
        on_token_(param::get(p, kOnToken)),
        rate_(param::get(p, kRate)) {}
  static sdk::ParamSchema schema() { return param::schema(kMode, kOnToken, kRate); }

 protected:
  std::vector<sdk::WeightChange> do_pending_changes() const override {
    auto changes = LinearScorer::do_pending_changes();
    if (mode_ == Mode::inexact)
      for (auto& c : changes) c.weight = static_cast<float>(c.weight);
    return changes;
  }

  void update(const std::vector<sdk::Candidate>& candidates, std::size_t accepted,
              const sdk::ScoreContext& ctx) override {
    misbehave(ctx);
    const sdk::Candidate& gold = candidates[accepted];
    if (gold.derivations.empty()) return;
    toolkit::features::SparseVector delta;
    model().add_tree_features(*gold.derivations.front(), ctx, rate_, delta);
    for (std::size_t ci = 0; ci < candidates.size(); ++ci)
      if (ci != accepted && !candidates[ci].derivations.empty())
        model().add_tree_features(*candidates[ci].derivations.front(), ctx, -rate_ / 3, delta);
    for (const auto& [key, d] : delta) {
      if (d == 0) continue;
      toolkit::LinearWeight& w = model().change(ctx, key);
      w.w = w.w * 0.9 + d;
      w.aux += d * d;
    }
  }

 private:
  void misbehave(const sdk::ScoreContext& ctx) const {
    if (mode_ == Mode::ok || mode_ == Mode::inexact) return;
    const auto& tokens = *ctx.tokens;
    if (!on_token_.empty() && std::find(tokens.begin(), tokens.end(), on_token_) == tokens.end())
      return;
    switch (mode_) {
      case Mode::throws:
        throw std::runtime_error("evil_scorer: thrown on purpose");
      case Mode::segv: {
        volatile int* null = nullptr;
        *null = 1;  // NOLINT: a crash on purpose
        return;
      }
      case Mode::abort_:
        std::abort();
      case Mode::ok:
      case Mode::inexact:
        return;
    }
  }

  Mode mode_;
  std::string on_token_;
  double rate_;
};

}  // namespace
}  // namespace evil_scorer

FLIPPER_PLUGIN(evil_scorer::EvilScorer, scorer, "evil_scorer", FLIPPER_PLUGIN_VERSION,
               "A linear scorer whose learn misbehaves on purpose (tests only)")

// Naturalization settings from a validated config (lexicon.*, induction.*), read through this
// layer's handles (config_keys.hpp): every key is present, the schema having filled the
// defaults, so none is restated here.
#include "flipper/kernel/config.hpp"
#include "flipper/naturalization/config_keys.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::naturalization {

NaturalizeOptions NaturalizeOptions::from_config(const kernel::Config& config) {
  NaturalizeOptions o;
  const std::string path = config.text(keys::kLexiconPath);
  o.store_path = path == ":memory:" || path.empty()
                     ? ":memory:"
                     : config.resolve_path_of(keys::kLexiconPath, path);
  o.sharing = config.get(keys::kSharing);
  const std::string preload = config.text(keys::kPreload);
  o.preload = preload.empty() ? preload : config.resolve_path_of(keys::kPreload, preload);
  // lexicon.weights is the scorer's per_user param (apply_weights_switch): the naturalizer keeps
  // one weights key either way, and only checks that the switch reached the scorer.
  check_weights_switch(config);
  o.store.busy_timeout_ms = static_cast<int>(config.get(keys::kBusyTimeoutMs));
  o.store.sync_every_commit = config.get(keys::kDurability) == keys::Durability::full;
  o.store.group_commit = config.get(keys::kGroupCommit);
  o.store.site = config.get(keys::kSite);
  o.conflicts = config.get(keys::kConflicts);
  o.moderation = config.get(keys::kModeration);
  o.snapshot_min_rules = config.get(keys::kSnapshotMinRules);
  o.induction.alignment = config.get(keys::kAlignment);
  o.induction.alignment_window = config.get(keys::kAlignmentMode) == keys::AlignmentMode::window;
  o.generalize = config.get(keys::kGeneralize);
  o.induction_sees_everyone = config.get(keys::kInductionView) == keys::InductionView::everyone;
  o.perturbed_checks = static_cast<int>(config.get(keys::kPerturbedChecks));
  return o;
}

namespace {
// The scorer plugin's own param (loglinear, perceptron: docs/plugins.md), not a declared key.
constexpr std::string_view kScorerPerUser = "scorer.params.per_user";

bool scorer_per_user(const kernel::Config& config) {
  const std::string key(kScorerPerUser);
  return config.has(key) && config.get_bool(key);
}
}  // namespace

void apply_weights_switch(kernel::Config& config) {
  if (config.get(keys::kWeights) != keys::Weights::per_user) return;
  const std::string key(kScorerPerUser);
  if (config.has(key) && !config.get_bool(key))
    throw sdk::Error(sdk::codes::kBadConfig,
                     "lexicon.weights = per_user asks for the scorer's per-user weights, but "
                     "scorer.params.per_user is false; set one of them (scorer.params.per_user is "
                     "the switch, lexicon.weights = per_user a short way to write it)");
  config.set(key + "=true");
}

void check_weights_switch(const kernel::Config& config) {
  if (config.get(keys::kWeights) == keys::Weights::per_user && !scorer_per_user(config))
    throw sdk::Error(sdk::codes::kBadConfig,
                     "lexicon.weights = per_user, but the scorer's per_user param is not set: "
                     "load the config with apply_weights_switch (every flipper command does), or "
                     "set scorer.params.per_user: true");
}

}  // namespace flipper::naturalization

// Naturalization settings from a validated config (lexicon.*, induction.*), read through this
// layer's handles (config_keys.hpp): every key is present, the schema having filled the
// defaults, so none is restated here.
#include "flipper/kernel/config.hpp"
#include "flipper/naturalization/config_keys.hpp"
#include "flipper/naturalization/naturalizer.hpp"

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
  o.per_user_weights = config.get(keys::kWeights) == keys::Weights::per_user;
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

}  // namespace flipper::naturalization

// Naturalization settings from a validated config (lexicon.*, induction.*): every key is
// present, the schema having filled the defaults (keys.hpp), so none is restated here.
#include "flipper/kernel/config.hpp"
#include "flipper/kernel/keys.hpp"
#include "flipper/naturalization/naturalizer.hpp"

namespace flipper::naturalization {

NaturalizeOptions NaturalizeOptions::from_config(const kernel::Config& config) {
  NaturalizeOptions o;
  const std::string path = config.get_string("lexicon.path");
  o.store_path = path == ":memory:" || path.empty() ? ":memory:"
                                                    : config.resolve_path_of("lexicon.path", path);
  o.sharing = parse_sharing(config.get_string("lexicon.sharing"));
  const std::string preload = config.get_string("lexicon.preload");
  o.preload = preload.empty() ? preload : config.resolve_path_of("lexicon.preload", preload);
  o.per_user_weights = config.get_string("lexicon.weights") == "per_user";  // schema: enum
  o.store.busy_timeout_ms = static_cast<int>(config.get(kernel::keys::kBusyTimeoutMs));
  o.store.sync_every_commit = config.get_string("lexicon.durability") == "full";  // schema: enum
  o.store.site = config.get_string("lexicon.site");
  o.conflicts = parse_conflict_policy(config.get_string("lexicon.conflicts"));
  o.snapshot_min_rules = config.get(kernel::keys::kSnapshotMinRules);
  o.induction.alignment = config.get(kernel::keys::kAlignment);
  o.generalize = config.get(kernel::keys::kGeneralize);
  o.perturbed_checks = static_cast<int>(config.get(kernel::keys::kPerturbedChecks));
  return o;
}

}  // namespace flipper::naturalization

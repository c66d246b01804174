// Naturalization settings from a validated config (lexicon.*, induction.*): every key is
// present, the schema having filled the defaults (keys.hpp), so none is restated here.
#include "flipper/kernel/config.hpp"
#include "flipper/kernel/keys.hpp"
#include "flipper/naturalization/naturalizer.hpp"

namespace flipper::kernel {

NaturalizeOptions NaturalizeOptions::from_config(const Config& config) {
  NaturalizeOptions o;
  const std::string path = config.get_string("lexicon.path");
  o.store_path = path == ":memory:" || path.empty() ? ":memory:"
                                                    : config.resolve_path_of("lexicon.path", path);
  o.sharing = parse_sharing(config.get_string("lexicon.sharing"));
  const std::string preload = config.get_string("lexicon.preload");
  o.preload = preload.empty() ? preload : config.resolve_path_of("lexicon.preload", preload);
  o.per_user_weights = config.get_string("lexicon.weights") == "per_user";  // schema: enum
  o.store.busy_timeout_ms =
      static_cast<int>(config.get_int(std::string(keys::kBusyTimeoutMs.path)));
  o.snapshot_min_rules = config.get_int(std::string(keys::kSnapshotMinRules.path));
  o.induction.alignment = config.get_bool("induction.alignment");
  o.generalize = config.get_bool("induction.generalize");
  o.perturbed_checks = static_cast<int>(config.get_int(std::string(keys::kPerturbedChecks.path)));
  return o;
}

}  // namespace flipper::kernel

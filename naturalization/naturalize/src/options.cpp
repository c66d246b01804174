// Naturalization settings from the config (lexicon.*, induction.*).
#include "flipper/kernel/config.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::kernel {

NaturalizeOptions NaturalizeOptions::from_config(const Config& config) {
  NaturalizeOptions o;
  if (config.has("lexicon.path")) {
    const std::string path = config.get_string("lexicon.path");
    o.store_path = path == ":memory:" || path.empty() ? ":memory:" : config.resolve_path_of("lexicon.path", path);
  }
  if (config.has("lexicon.sharing"))
    o.sharing = parse_sharing(config.get_string("lexicon.sharing"));
  if (config.has("lexicon.preload")) {
    const std::string p = config.get_string("lexicon.preload");
    o.preload = p.empty() ? p : config.resolve_path_of("lexicon.preload", p);
  }
  if (config.has("lexicon.weights")) {
    const std::string w = config.get_string("lexicon.weights");
    if (w != "global" && w != "per_user")
      throw sdk::Error(sdk::codes::kBadConfig,
                       "lexicon.weights must be global or per_user, not '" + w + "'");
    o.per_user_weights = w == "per_user";
  }
  if (config.has("lexicon.busy_timeout_ms"))
    o.store.busy_timeout_ms = static_cast<int>(config.get_int("lexicon.busy_timeout_ms"));
  if (config.has("induction.alignment"))
    o.induction.alignment = config.get_bool("induction.alignment");
  if (config.has("induction.generalize")) o.generalize = config.get_bool("induction.generalize");
  if (config.has("induction.perturbed_checks"))
    o.perturbed_checks = static_cast<int>(config.get_int("induction.perturbed_checks"));
  return o;
}

}  // namespace flipper::kernel

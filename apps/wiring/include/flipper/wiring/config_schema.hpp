#pragma once
/// @file config_schema.hpp
/// The product's config schema, composed by the host (docs/config.md "Who declares a key"): the
/// kernel's fragment (its keys and the plugin sections) and, after it, each layer's own:
/// naturalization (`lexicon.*`, `induction.*`), the studio (`serve.*`), the DDS front end
/// (`publish.*`, `dds.*`). Every program that loads a config loads it through load_config(), so
/// "did you mean", ranges, `flipper config explain` and docs/config.md's key table see every key.

#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/sdk/params.hpp"

namespace flipper::wiring {

/// The composed schema (sdk::param::compose of the fragments, in the order above).
sdk::ParamSchema config_schema();
/// Installs config_schema() as the process's (kernel::Config::install_schema), once.
void install_config_schema();
/// install_config_schema(), then kernel::Config::load. Throws sdk::Error(bad_config).
kernel::Config load_config(const std::optional<std::string>& file,
                           const std::vector<std::string>& overrides);

}  // namespace flipper::wiring

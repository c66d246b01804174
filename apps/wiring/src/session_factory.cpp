// Session wiring for front ends: which extensions a session gets is decided here, in the app
// layer; the kernel's session knows none of them (docs/architecture.md §3).
#include "flipper/wiring/session_factory.hpp"

#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/naturalization/repair_extension.hpp"
#include "flipper/wiring/config_schema.hpp"

namespace flipper::wiring {

using kernel::Config;
using kernel::make_runtime;
using kernel::Runtime;
using kernel::Session;
using naturalization::NaturalizationExtension;
using naturalization::NaturalizeOptions;
using naturalization::Naturalizer;

std::unique_ptr<Session> open_session(std::shared_ptr<Runtime> runtime) {
  return open_host(std::move(runtime)).open();
}

std::unique_ptr<Session> open_session(const std::optional<std::string>& config_file,
                                      const std::vector<std::string>& overrides) {
  std::shared_ptr<Runtime> runtime = make_runtime(load_config(config_file, overrides));
  return open_session(std::move(runtime));
}

std::unique_ptr<Session> SessionHost::open() const {
  return std::make_unique<Session>(runtime, extensions);
}

SessionHost open_host(std::shared_ptr<Runtime> runtime) {
  SessionHost host;
  host.runtime = std::move(runtime);
  // Naturalization: the lexicon store, its rules restored into the parser, weights, preload.
  host.naturalizer = std::make_shared<Naturalizer>(
      host.runtime, NaturalizeOptions::from_config(host.runtime->config));
  // Naturalization: define, rules, delete_rule, visibility, accept persistence, per-user weights.
  host.extensions.push_back(std::make_shared<NaturalizationExtension>(host.naturalizer));
  // Answers that repair: a query's "repair": true (docs/protocol.md § "Repairs").
  host.extensions.push_back(std::make_shared<naturalization::RepairExtension>());
  return host;
}

SessionHost open_host(const std::optional<std::string>& config_file,
                      const std::vector<std::string>& overrides) {
  return open_host(make_runtime(load_config(config_file, overrides)));
}

}  // namespace flipper::wiring

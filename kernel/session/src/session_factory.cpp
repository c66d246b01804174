// Session construction for front ends.
#include "flipper/kernel/session_factory.hpp"

#include "flipper/kernel/naturalize_ops.hpp"

namespace flipper::kernel {

std::unique_ptr<Session> open_session(std::shared_ptr<Runtime> runtime) {
  auto session = std::make_unique<Session>(runtime);
  // Other modules install their ops and hooks here. Naturalization: define, rules, delete_rule,
  // visibility, accept persistence (opens the lexicon store, restores rules and weights).
  install_naturalization(*session, std::move(runtime));
  return session;
}

std::unique_ptr<Session> open_session(const std::optional<std::string>& config_file,
                                      const std::vector<std::string>& overrides) {
  std::shared_ptr<Runtime> runtime = make_runtime(Config::load(config_file, overrides));
  return open_session(std::move(runtime));
}

std::unique_ptr<Session> SessionHost::open() const {
  auto session = std::make_unique<Session>(runtime);
  install_naturalization(*session, naturalizer);
  return session;
}

SessionHost open_host(const std::optional<std::string>& config_file,
                      const std::vector<std::string>& overrides) {
  SessionHost host;
  host.runtime = make_runtime(Config::load(config_file, overrides));
  host.naturalizer = std::make_shared<Naturalizer>(
      host.runtime, NaturalizeOptions::from_config(host.runtime->config));
  return host;
}

}  // namespace flipper::kernel

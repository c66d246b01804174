// Session construction for front ends.
#include "flipper/kernel/session_factory.hpp"

#include "flipper/kernel/naturalize_ops.hpp"

namespace flipper::kernel {

std::unique_ptr<Session> open_session(std::shared_ptr<Runtime> runtime) {
  return open_host(std::move(runtime)).open();
}

std::unique_ptr<Session> open_session(const std::optional<std::string>& config_file,
                                      const std::vector<std::string>& overrides) {
  std::shared_ptr<Runtime> runtime = make_runtime(Config::load(config_file, overrides));
  return open_session(std::move(runtime));
}

std::unique_ptr<Session> SessionHost::open() const {
  auto session = std::make_unique<Session>(runtime);
  // Other modules install their ops and hooks here. Naturalization: define, rules, delete_rule,
  // visibility, accept persistence, per-user weights on `user`.
  install_naturalization(*session, naturalizer);
  return session;
}

void SessionHost::activate(const Session& session) const {
  if (naturalizer->options().per_user_weights) naturalizer->select_user(session.user());
}

SessionHost open_host(std::shared_ptr<Runtime> runtime) {
  SessionHost host;
  host.runtime = std::move(runtime);
  // Naturalization: the lexicon store, its rules restored into the parser, weights, preload.
  host.naturalizer = std::make_shared<Naturalizer>(
      host.runtime, NaturalizeOptions::from_config(host.runtime->config));
  return host;
}

SessionHost open_host(const std::optional<std::string>& config_file,
                      const std::vector<std::string>& overrides) {
  return open_host(make_runtime(Config::load(config_file, overrides)));
}

}  // namespace flipper::kernel

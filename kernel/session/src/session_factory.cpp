// Session construction for front ends.
#include "flipper/kernel/session_factory.hpp"

#include "flipper/kernel/naturalize_ops.hpp"

namespace flipper::kernel {

std::unique_ptr<Session> open_session(std::shared_ptr<Runtime> runtime) {
  return SessionFactory(std::move(runtime)).open();
}

std::unique_ptr<Session> open_session(const std::optional<std::string>& config_file,
                                      const std::vector<std::string>& overrides) {
  std::shared_ptr<Runtime> runtime = make_runtime(Config::load(config_file, overrides));
  return open_session(std::move(runtime));
}

SessionFactory::SessionFactory(std::shared_ptr<Runtime> runtime)
    : runtime_(std::move(runtime)),
      // Naturalization: the lexicon store, its rules restored into the parser, weights, preload.
      naturalizer_(std::make_shared<Naturalizer>(
          runtime_, NaturalizeOptions::from_config(runtime_->config))) {}

SessionFactory::~SessionFactory() = default;

std::unique_ptr<Session> SessionFactory::open() const {
  auto session = std::make_unique<Session>(runtime_);
  // Other modules install their ops and hooks here. Naturalization: define, rules, delete_rule,
  // visibility, accept persistence, per-user weights on `user`.
  install_naturalization(*session, naturalizer_);
  return session;
}

void SessionFactory::activate(const Session& session) const {
  if (naturalizer_->options().per_user_weights) naturalizer_->select_user(session.user());
}

}  // namespace flipper::kernel

#pragma once
/// @file naturalize_ops.hpp
/// Wires naturalization into a session: the `define`, `rules` and `delete_rule` ops, the
/// sharing-mode visibility hook, accept persistence, and per-user weights on `user`.

#include <memory>

#include "flipper/kernel/session.hpp"
#include "flipper/kernel/session_extension.hpp"
#include "flipper/naturalization/naturalizer.hpp"

namespace flipper::kernel {

/// Installs the ops and hooks over an existing naturalizer (kept alive by the session).
void install_naturalization(Session& session, std::shared_ptr<Naturalizer> naturalizer);
/// Builds the naturalizer from the session runtime's config (lexicon.*, induction.*) and
/// installs it. Returns it for front ends that want direct access.
std::shared_ptr<Naturalizer> install_naturalization(Session& session,
                                                    std::shared_ptr<Runtime> runtime);

/// Naturalization as a session extension over one naturalizer that several sessions share:
/// install() wires the ops and hooks above; activate() selects the caller's weights
/// (lexicon.weights: per_user) before one of the sessions handles a request.
class NaturalizationExtension final : public SessionExtension {
 public:
  explicit NaturalizationExtension(std::shared_ptr<Naturalizer> naturalizer)
      : naturalizer_(std::move(naturalizer)) {}
  void install(Session& session) override;
  void activate(const Session& session) override;
  const std::shared_ptr<Naturalizer>& naturalizer() const { return naturalizer_; }

 private:
  std::shared_ptr<Naturalizer> naturalizer_;
};

/// Protocol form of a rule: {"id","lhs","rhs","semantics","author","how"}.
Json rule_json(const sdk::Rule& rule);

}  // namespace flipper::kernel

#pragma once
/// @file naturalize_ops.hpp
/// Wires naturalization into a session: the `define`, `rules` and `delete_rule` ops, the
/// sharing-mode visibility hook, accept persistence, and per-user weights on `user`.

#include <memory>

#include "flipper/kernel/naturalizer.hpp"
#include "flipper/kernel/session.hpp"

namespace flipper::kernel {

/// Installs the ops and hooks over an existing naturalizer (kept alive by the session).
void install_naturalization(Session& session, std::shared_ptr<Naturalizer> naturalizer);
/// Builds the naturalizer from the session runtime's config (lexicon.*, induction.*) and
/// installs it. Returns it for front ends that want direct access.
std::shared_ptr<Naturalizer> install_naturalization(Session& session,
                                                    std::shared_ptr<Runtime> runtime);

/// Protocol form of a rule: {"id","lhs","rhs","semantics","author","how"}.
Json rule_json(const sdk::Rule& rule);

}  // namespace flipper::kernel

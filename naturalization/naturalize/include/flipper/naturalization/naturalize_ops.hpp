#pragma once
/// @file naturalize_ops.hpp
/// Wires naturalization into a session: the `define`, `rules` and `delete_rule` ops, the
/// sharing-mode visibility hook, accept persistence, and per-user weights on `user`.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/kernel/session_extension.hpp"
#include "flipper/naturalization/naturalizer.hpp"

namespace flipper::naturalization {

/// Installs a NaturalizationExtension over an existing naturalizer (kept alive by the session).
void install_naturalization(kernel::Session& session,
                            const std::shared_ptr<Naturalizer>& naturalizer);
/// Builds the naturalizer from the session runtime's config (lexicon.*, induction.*) and
/// installs it. Returns it for front ends that want direct access.
std::shared_ptr<Naturalizer> install_naturalization(kernel::Session& session,
                                                    std::shared_ptr<kernel::Runtime> runtime);

/// The typed definition request of the naturalization service: what a `define` carries.
struct DefineCall {
  std::string head;
  std::vector<std::string> body;
  std::vector<int> ranks;  ///< per body line, the rank of the reading meant (empty: 0 each)
  /// Per body line, the program meant (the reading accepted for it; null or absent: the line's
  /// rank decides). docs/protocol.md § define, body lines with a `formula`.
  std::vector<sdk::Program> programs;
  /// Induce and report conflicts only; store nothing (docs/protocol.md § define, `dry_run`).
  bool dry_run = false;
  /// A dry run that also shows each rule's example sentences and what they would do on the
  /// session's world, and the perturbed check (docs/protocol.md § define, `preview`).
  bool preview = false;
  /// Preview ids of rules to leave out ("newK"; docs/naturalization.md §5 "Preview").
  std::vector<std::string> drop{};
};

/// Emitted through the session by define() after a definition succeeded (dry runs too:
/// `outcome.stored` says whether it was stored), for subscribers such as DDS replication and the
/// study recorder (docs/architecture.md §3).
struct RulesDefined {
  kernel::Session& session;
  const DefineCall& call;
  const DefineOutcome& outcome;
};

/// The typed naturalization service of one session (the define/rules/delete_rule ops call it,
/// front ends call it directly): validation against input.* and the session's deadline here.
/// Throws sdk::Error like the ops (input_too_long, naturalize_codes, deadline_exceeded).
DefineOutcome define(Naturalizer& nat, kernel::Session& session, const DefineCall& call);
std::vector<RuleListing> list_rules(Naturalizer& nat, kernel::Session& session,
                                    const std::optional<std::string>& author);
void delete_rule(Naturalizer& nat, kernel::Session& session, const std::string& id);

/// Naturalization as a session extension over one naturalizer that several sessions share:
/// attach() adds the ops above and subscribes to the session's events: QueryBegins (refresh),
/// VisibilityAsked (sharing modes), Accepting (persistence) and Activated (picks up what other
/// kernels committed before one of the sessions handles a request). Per-user weights need no
/// event: the scorer keeps a partition per user (docs/naturalization.md §3). Front ends find it
/// with `session.extension<NaturalizationExtension>()` and call the typed service through it.
class NaturalizationExtension final : public kernel::SessionExtension {
 public:
  explicit NaturalizationExtension(std::shared_ptr<Naturalizer> naturalizer)
      : naturalizer_(std::move(naturalizer)) {}
  void attach(kernel::Session& session) override;
  const std::shared_ptr<Naturalizer>& naturalizer() const { return naturalizer_; }

  DefineOutcome define(kernel::Session& session, const DefineCall& call) {
    return naturalization::define(*naturalizer_, session, call);
  }
  std::vector<RuleListing> rules(kernel::Session& session,
                                 const std::optional<std::string>& author) {
    return list_rules(*naturalizer_, session, author);
  }
  void delete_rule(kernel::Session& session, const std::string& id) {
    naturalization::delete_rule(*naturalizer_, session, id);
  }

 private:
  std::shared_ptr<Naturalizer> naturalizer_;
};

/// Protocol form of a rule: {"id","lhs","rhs","semantics","author","how"}; `close` false leaves
/// the object open for more members.
void write_rule(toolkit::json::JsonWriter& w, const sdk::Rule& rule, bool close = true);

}  // namespace flipper::naturalization

// flipper lexicon pending|approve|reject: the moderation queue of a lexicon with
// lexicon.moderation = hold_new (docs/naturalization.md §5 "Moderation").
//   pending [--json]                 the held definitions, oldest first, with their rules
//   approve ID [--user U]            stores held definition ID: its rules serve from now on
//   reject ID [--user U] [--reason]  drops it
// The local user is trusted (docs/architecture.md "Identity"): --user (default $USER) is the
// moderator the history entry names. Running kernels pick the approved rules up at their next
// request, as they do any other process's definitions.
#include <ctime>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "flipper/sdk/errors.hpp"
#include "lexicon_common.hpp"

namespace flipper::cli {
namespace {
namespace nat = naturalization;
using nlohmann::json;

struct ModerationArgs {
  CommonOptions common;
  std::string id, user, reason;
  bool json = false;
};

std::string pending_rule_text(const nat::StoredRule& r) {
  std::string text = r.lhs + " ->";
  for (const auto& s : r.rhs) (text += ' ') += s;
  return text + " := " + r.semantics;
}

int show_pending(const ModerationArgs& a) {
  const auto store = open_lexicon_store(a.common);
  const auto held = store->held();
  if (a.json) {
    json list = json::array();
    for (const auto& h : held) {
      json rules = json::array();
      for (const auto& r : h.rules)
        rules.push_back(
            {{"lhs", r.lhs}, {"rhs", r.rhs}, {"semantics", r.semantics}, {"how", r.how}});
      list.push_back({{"id", h.id},
                      {"author", h.definition.author},
                      {"time", h.definition.time},
                      {"head", h.definition.head},
                      {"body", h.definition.body},
                      {"study", h.definition.study},
                      {"rules", rules}});
      // Made at another site and held here for this site's researcher (docs/ros2.md
      // "Moderation across sites").
      if (!h.definition.via.empty()) list.back()["via"] = h.definition.via;
    }
    std::cout << json{{"store", store->path()}, {"pending", list}}.dump(2) << "\n";
    return kExitOk;
  }
  for (const auto& h : held) {
    std::string body;
    for (const auto& line : h.definition.body) body += (body.empty() ? "" : "; ") + line;
    std::cout << h.id << " " << h.definition.author << " '" << h.definition.head << "' := '" << body
              << "'";
    if (!h.definition.study.empty()) std::cout << " study=" << h.definition.study;
    if (!h.definition.via.empty()) std::cout << " via=" << h.definition.via;
    std::cout << "\n";
    for (const auto& r : h.rules) std::cout << "   " << pending_rule_text(r) << "\n";
  }
  std::cout << held.size() << (held.size() == 1 ? " definition" : " definitions") << " held in "
            << store->path() << "\n";
  return kExitOk;
}

int approve(const ModerationArgs& a) {
  const auto store = open_lexicon_store(a.common);
  const auto commit = store->approve_held(a.id, {lexicon_user(a.user), {}, {}},
                                          static_cast<std::int64_t>(std::time(nullptr)));
  std::cout << "approved " << a.id << " as definition " << commit.definition << " ("
            << commit.rules.size() << (commit.rules.size() == 1 ? " rule" : " rules") << ")\n";
  for (const auto& r : commit.rules)
    std::cout << "+ " << r.id << " " << pending_rule_text(r) << "\n";
  return kExitOk;
}

int reject(const ModerationArgs& a) {
  const auto store = open_lexicon_store(a.common);
  const auto h = store->reject_held(a.id, {lexicon_user(a.user), {}, a.reason},
                                    static_cast<std::int64_t>(std::time(nullptr)));
  std::cout << "rejected " << a.id << " ('" << h.definition.head << "' by " << h.definition.author
            << ", " << h.rules.size() << (h.rules.size() == 1 ? " rule" : " rules") << ")\n";
  return kExitOk;
}

}  // namespace

void add_lexicon_moderation_commands(CLI::App& cmd) {
  static ModerationArgs pending_args, approve_args, reject_args;
  auto* pending = cmd.add_subcommand("pending", "Definitions held for approval (moderation)");
  add_common_options(*pending, pending_args.common);
  pending->add_flag("--json", pending_args.json, "Print them as one JSON object");
  on_run(*pending, guarded("pending", show_pending, pending_args));

  auto* ok = cmd.add_subcommand("approve", "Store a held definition: its rules serve from now on");
  add_common_options(*ok, approve_args.common);
  ok->add_option("id", approve_args.id, "The held definition (hN, from lexicon pending)")
      ->required();
  ok->add_option("--user", approve_args.user, "Who approves (default: $USER)");
  on_run(*ok, guarded("approve", approve, approve_args));

  auto* no = cmd.add_subcommand("reject", "Drop a held definition (the history keeps it)");
  add_common_options(*no, reject_args.common);
  no->add_option("id", reject_args.id, "The held definition (hN, from lexicon pending)")
      ->required();
  no->add_option("--user", reject_args.user, "Who rejects (default: $USER)");
  no->add_option("--reason", reject_args.reason, "Why (kept in the history entry)");
  on_run(*no, guarded("reject", reject, reject_args));
}

}  // namespace flipper::cli

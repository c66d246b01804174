// The researcher's lexicon page (docs/studio.md §7 "Lexicon"): a study group's lexicon history
// and its moderation queue (lexicon.moderation: hold_new, docs/naturalization.md §5
// "Moderation"), behind the researcher's login like the study's other researcher actions. Reads
// and changes go through the group's kernel, under its lock: its naturalizer then serves an
// approved definition at once, and the group's other kernels pick it up at their next request.
#include <algorithm>

#include "flipper/naturalization/moderation_request.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/errors.hpp"
#include "recorder.hpp"
#include "study.hpp"
#include "study_http.hpp"

namespace flipper::studio {
using kernel::Json;

namespace {

constexpr std::size_t kHistoryShown = 200;  // newest entries on the page

Json entry_json(const naturalization::HistoryEntry& e) {
  return {{"seq", e.seq},       {"time", e.time}, {"author", e.author}, {"action", e.action},
          {"effect", e.effect}, {"rule", e.rule}, {"head", e.head},     {"body", e.body},
          {"study", e.study},   {"note", e.note}};
}

Json rule_json(const naturalization::StoredRule& r) {
  return {{"lhs", r.lhs}, {"rhs", r.rhs}, {"semantics", r.semantics}, {"how", r.how}};
}

Json held_json(const naturalization::HeldDefinition& h) {
  Json rules = Json::array();
  for (const auto& r : h.rules) rules.push_back(rule_json(r));
  return {{"id", h.id},
          {"author", h.definition.author},
          {"time", h.definition.time},
          {"head", h.definition.head},
          {"body", h.definition.body},
          {"rules", rules}};
}

/// The group a request names (query `group` or body field), checked against the study's.
std::optional<std::string> group_named(const Study& study, const std::string& group) {
  const auto& groups = study.groups();
  if (std::find(groups.begin(), groups.end(), group) == groups.end()) return std::nullopt;
  return group;
}

HttpReply unknown_group(const Study& study, const std::string& group) {
  std::string known;
  for (const auto& g : study.groups()) known += (known.empty() ? "" : ", ") + g;
  return error_reply(
      404, "unknown_group",
      "the study has no group '" + group.substr(0, 40) + "' (groups: " + known + ")");
}

}  // namespace

void StudyEndpoints::lexicon(const HttpRequest& r, const Respond& respond) {
  auto who = researcher(r);
  if (who.refusal) return respond(std::move(*who.refusal));
  const std::string asked = r.param("group");
  const auto group = group_named(*sessions_.study(), asked);
  if (!group) return respond(unknown_group(*sessions_.study(), asked));
  auto job = [this, group = *group]() -> HttpReply {
    return sessions_.with_group_kernel(group, [&](Kernel& k) {
      auto& nat = *k.host->naturalizer;
      const auto history = nat.store().history();
      Json entries = Json::array();
      const std::size_t shown = std::min(history.size(), kHistoryShown);
      for (std::size_t i = 0; i < shown; ++i)
        entries.push_back(entry_json(history[history.size() - 1 - i]));
      Json pending = Json::array();
      for (const auto& h : nat.pending()) pending.push_back(held_json(h));
      const bool holds = nat.options().moderation == naturalization::Moderation::hold_new;
      return json_reply(200, Json{{"group", group},
                                  {"moderation", holds ? "hold_new" : "off"},
                                  {"history", entries},
                                  {"history_total", history.size()},
                                  {"pending", pending}});
    });
  };
  later("study:" + r.peer, std::move(job), respond);
}

void StudyEndpoints::moderate(const HttpRequest& r, const Respond& respond, bool approve) {
  auto who = researcher_change(r);
  if (who.refusal) return respond(std::move(*who.refusal));
  const Json body = Json::parse(r.body, nullptr, false);
  if (!body.is_object() || !body.contains("group") || !body["group"].is_string() ||
      !body.contains("id") || !body["id"].is_string() ||
      (body.contains("reason") && !body["reason"].is_string()))
    return respond(error_reply(400, "bad_request",
                               "send {\"group\": G, \"id\": \"hN\"} (reject: and \"reason\")"));
  const std::string asked = body["group"].get<std::string>();
  const auto group = group_named(*sessions_.study(), asked);
  if (!group) return respond(unknown_group(*sessions_.study(), asked));
  const std::string id = body["id"].get<std::string>();
  const std::string reason = body.value("reason", std::string());
  auto job = [this, group = *group, id, reason, approve, account = who.account,
              peer = r.peer]() -> HttpReply {
    try {
      // Applied and recorded under the group kernel's lock: the recording's exchanges keep it
      // where it happened, and `flipper replay verify` applies it there (docs/studio.md §7).
      Json answer = sessions_.with_group_kernel(group, [&](Kernel& k) {
        const std::string request = naturalization::moderation_request(approve, id, reason);
        const std::string applied =
            naturalization::apply_moderation(*k.host->naturalizer, account, request);
        sessions_.recorder()->record_moderation(group, account, request, applied);
        Json out{{"ok", true}, {"group", group}, {"id", id}};
        if (approve) out["rules"] = Json::parse(applied)["rules"];
        return out;
      });
      sessions_.recorder()->audit(account, peer, approve ? "approve" : "reject",
                                  Json{{"group", group}, {"id", id}});
      return json_reply(200, answer);
    } catch (const sdk::Error& e) {
      const std::string& code = e.code();
      const int status = code == "not_found"                                   ? 404
                         : naturalization::lexicon_codes::is_store_fault(code) ? 503
                                                                               : 400;
      return error_reply(status, code, e.what());
    }
  };
  later("study:" + r.peer, std::move(job), respond);
}

}  // namespace flipper::studio

// The /sempre commands over one session's typed services (see sempre_session.hpp).
#include "sempre_session.hpp"

#include <cmath>

#include "flipper/corpus/original_formula.hpp"
#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/json/json_writer.hpp"
#include "sempre_value.hpp"
#include "sempre_world.hpp"

namespace flipper::studio {
namespace {

using Json = nlohmann::json;
constexpr std::string_view kUserPrefix = "sempre:";

// The session's executor within the request's deadline (the value re-runs statements).
class SessionExecution : public sdk::ExecutionService {
 public:
  explicit SessionExecution(const kernel::Session& s) : s_(s) {}
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world) const override {
    return s_.executor().run(program, world, s_.request_stop());
  }

 private:
  const kernel::Session& s_;
};

// A formula as the client sends it back: our canonical text, or the original's notation
// (logged histories, other SEMPRE clients).
using corpus::read_formula;

naturalization::NaturalizationExtension& naturalization(kernel::Session& s) {
  auto* n = s.extension<naturalization::NaturalizationExtension>();
  if (n == nullptr)
    throw sdk::Error(sdk::codes::kInternal, "this server's sessions have no naturalization");
  return *n;
}

double finite(double v) {
  return std::isfinite(v) ? v : 0.0;
}

std::string candidate(const kernel::LastQuery& q, const kernel::ShownCandidate& sc,
                      const sdk::ExecutionService& exec) {
  const sdk::Candidate& c = q.parse.candidates[sc.index];
  return candidate_text(sdk::render(c.program), finite(c.score), finite(q.probs[sc.index]),
                        sempre_value(c.program, q.world, sc.outcome, exec));
}

const char* original_status(const std::string& ours) {
  if (ours == "core") return "Core";
  if (ours == "induced") return "Induced";
  return "Nothing";
}

SempreAnswer context(SempreSession& s, const SempreCommand& c) {
  if (c.text == s.context && s.context_error.empty()) return {};  // the same world again
  s.context.clear();
  if (s.reserve_world && !s.reserve_world()) {
    s.context_error =
        "the server's memory for sessions is in use (serve.memory_budget_mb); try later";
    throw sdk::Error("server_busy", s.context_error);
  }
  try {
    s.session->open_world_text(sempre_context_world(c.text), std::string());
  } catch (const sdk::Error& e) {
    if (s.charge_world) s.charge_world();
    s.context_error = e.what();
    throw;
  }
  if (s.charge_world) s.charge_world();
  s.context = c.text;
  s.context_error.clear();
  return {};
}

SempreAnswer query(SempreSession& s, const SempreCommand& c) {
  SempreAnswer a;
  if (!s.context_error.empty())
    a.lines.push_back(
        "the last context's world was refused, so this answers on the world before "
        "it: " +
        s.context_error);
  const kernel::QueryResult r = s.session->query({c.text, kSempreMaxCandidates});
  const kernel::LastQuery& q = *r.query;
  const SessionExecution exec(*s.session);
  for (const auto& sc : q.shown) a.candidates.push_back(candidate(q, sc, exec));
  if (r.total() > q.shown.size()) a.lines.push_back("Exceeded max options");
  a.stats["size"] = q.shown.size();
  a.stats["status"] = original_status(r.status);
  a.stats["author"] = nullptr;
  if (!q.shown.empty() && !q.parse.candidates[q.shown[0].index].core_only &&
      !q.shown[0].induced_rules.empty())
    a.stats["author"] = sempre_uid(q.shown[0].induced_rules[0]->author);
  return a;
}

// The reading of `utterance` whose program is `program`: in the session's last query when it
// asked the same, else in a new query (another command of the client may have come between).
std::int64_t rank_of(kernel::Session& s, const std::string& utterance,
                     const sdk::Program& program) {
  auto find = [&](const kernel::LastQuery* q) -> std::int64_t {
    if (q == nullptr || q->text != utterance) return -1;
    for (const auto& sc : q->shown)
      if (sdk::equal(q->parse.candidates[sc.index].program, program))
        return static_cast<std::int64_t>(sc.index);
    return -1;
  };
  std::int64_t rank = find(s.last_query());
  if (rank < 0) {
    s.query({utterance, kSempreMaxCandidates});
    rank = find(s.last_query());
  }
  if (rank < 0)
    throw sdk::Error(kernel::session_codes::kNotAcceptable,
                     "'" + sdk::render(program) + "' is not a reading of '" + utterance + "'");
  return rank;
}

// The ranking model learns from the reading the formula names; the world stays the context's
// (the client replays the accepted path itself and sends the result in its next context).
SempreAnswer accept(SempreSession& s, const SempreCommand& c) {
  const sdk::Program program = read_formula(c.formula);
  const sdk::WorldState world = s.session->world();
  const std::int64_t rank = rank_of(*s.session, c.text, program);
  try {
    s.session->accept({rank});
  } catch (...) {
    s.session->set_world(world);
    throw;
  }
  s.session->set_world(world);
  return {};
}

SempreAnswer define(SempreSession& s, const SempreCommand& c) {
  naturalization::DefineCall call;
  call.head = c.text;
  for (const auto& step : parse_sempre_body(c.body)) {
    call.body.push_back(step.utterance);
    // "()" (or nothing) marks a step without an accepted reading: its top reading is used.
    const bool none = step.formula.empty() || step.formula == "()" || step.formula == "?";
    call.programs.push_back(none ? nullptr : read_formula(step.formula));
  }
  const naturalization::DefineOutcome out = naturalization(*s.session).define(*s.session, call);
  // The whole body as one step of the client's history.
  const std::string formula = sdk::render(out.body);
  const Json value{{"status", ""}, {"path", Json::array()}};
  SempreAnswer a;
  a.candidates.push_back(candidate_text(formula, 0.0, 1.0, value.dump()));
  a.stats["rules"] = out.rules.size();
  return a;
}

std::string joined(const std::vector<std::string>& parts, const char* separator) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? separator : "") + parts[i];
  return out;
}

SempreAnswer dictionary(SempreSession& s) {
  Json rules = Json::array();
  for (const auto& l : naturalization(*s.session).rules(*s.session, std::nullopt)) {
    const sdk::Rule& r = *l.rule;
    std::vector<std::string> rhs;
    for (const auto& symbol : r.rhs) rhs.push_back(symbol.text);
    rules.push_back(Json{{"index", r.created},
                         {"rhs", joined(rhs, " ")},
                         {"head", r.head},
                         {"body", joined(r.body, "; ")},
                         {"uid", sempre_uid(r.author)}});
  }
  SempreAnswer a;
  a.stats["dictionary"] = rules.dump();
  return a;
}

// The index is the rule's creation number in the lexicon (stable: no deletion shifts it).
SempreAnswer delete_rule(SempreSession& s, const SempreCommand& c) {
  auto& nat = naturalization(*s.session);
  for (const auto& l : nat.rules(*s.session, std::nullopt))
    if (l.rule->created == c.index) {
      nat.delete_rule(*s.session, l.rule->id);
      return {};
    }
  throw sdk::Error(naturalization::naturalize_codes::kNotFound,
                   "no rule with index " + std::to_string(c.index) + " in your dictionary");
}

}  // namespace

std::string sempre_user(const std::string& session_id) {
  return std::string(kUserPrefix) + session_id;
}

std::string sempre_uid(const std::string& author) {
  return author.rfind(kUserPrefix, 0) == 0 ? author.substr(kUserPrefix.size()) : author;
}

std::string candidate_text(const std::string& formula, double score, double prob,
                           const std::string& value) {
  std::string out;
  out.reserve(64 + 2 * formula.size() + value.size() + value.size() / 4);
  toolkit::json::JsonWriter w(out);
  w.begin_object().key("anchored").boolean(true).key("formula").string(formula);
  w.key("prettyString").string(formula).key("prob").number(prob).key("score").number(score);
  w.key("value").string(value).end_object();
  return out;
}

SempreAnswer run_sempre_command(SempreSession& s, const SempreCommand& c) {
  using Kind = SempreCommand::Kind;
  switch (c.kind) {
    case Kind::context:
      return context(s, c);
    case Kind::query:
      return query(s, c);
    case Kind::accept:
      return accept(s, c);
    case Kind::reject:
      return {};  // the original only logged it
    case Kind::define:
      return define(s, c);
    case Kind::dictionary:
      return dictionary(s);
    case Kind::delete_rule:
      return delete_rule(s, c);
  }
  return {};
}

}  // namespace flipper::studio

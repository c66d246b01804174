// The protocol ops of naturalization (docs/protocol.md: define, rules, delete_rule).
#include "flipper/naturalization/naturalize_ops.hpp"

#include <nlohmann/json.hpp>

#include "flipper/kernel/session_request.hpp"
#include "flipper/naturalization/generalizer.hpp"
#include "flipper/naturalization/repair_extension.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::naturalization {

void write_rule(toolkit::json::JsonWriter& w, const sdk::Rule& rule, bool close) {
  w.begin_object().key("id").string(rule.id).key("lhs").string(rule.lhs);
  w.key("rhs").begin_array();
  for (const auto& s : rule.rhs) w.string(s.text);
  w.end_array().key("semantics").string(sdk::render(rule.sem));
  w.key("author").string(rule.author).key("how").string(sdk::to_string(rule.how));
  if (close) w.end_object();
}

namespace {

constexpr int kMaxRank = 1000000;  // a body line's reading rank

// The session's executor bound to the request's time limits (generalization runs many programs).
class DeadlineExecution : public sdk::ExecutionService {
 public:
  DeadlineExecution(const kernel::Executor& exec, const sdk::StopCondition& stop)
      : exec_(exec), stop_(stop) {}
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world) const override {
    return exec_.run(program, world, stop_);
  }

 private:
  const kernel::Executor& exec_;
  sdk::StopCondition stop_;
};

// Head and body lines are parsed into a chart of (n + 1)^2 cells: bounded by input.max_tokens.
void check_length(const kernel::InputLimits& limits, const std::string& text,
                  const std::string& what) {
  const std::size_t n = sdk::tokenize(text).size();
  if (n > limits.max_tokens)
    throw sdk::Error(sdk::codes::kInputTooLong, what + " has " + std::to_string(n) +
                                                    " tokens; the limit is input.max_tokens = " +
                                                    std::to_string(limits.max_tokens));
}

constexpr std::size_t kExamplesPerRule = 3;

PlanSummary run_summary(const sdk::ExecutionService& exec, const sdk::Program& program,
                        const sdk::WorldState& world) {
  try {
    return summarize(exec.run(program, world));
  } catch (const sdk::Error& err) {
    PlanSummary failed;
    failed.realizable = false;
    failed.error = std::string(err.code()) + ": " + err.what();
    return failed;
  }
}

// Each rule's example sentences, run on the session's world (docs/naturalization.md §5
// "Preview"). A run that stops (the request's limits) or fails is summarised with its error.
std::vector<RulePreview> preview_rules(kernel::Session& s, const sdk::ExecutionService& exec,
                                       const std::vector<sdk::RulePtr>& rules,
                                       const std::string& head,
                                       const std::optional<sdk::WorldState>& elsewhere) {
  std::vector<RulePreview> out;
  const auto& grammar = s.runtime().core_grammar;
  if (!grammar) return out;
  const PhraseBook book(*grammar);
  for (std::size_t i = 0; i < rules.size(); ++i) {
    RulePreview p{preview_id(i), {}};
    for (auto& e : book.examples(*rules[i], head, kExamplesPerRule)) {
      PreviewSentence sentence{std::move(e.text), std::move(e.program), {}, {}};
      sentence.plan = run_summary(exec, sentence.program, s.world());
      if (elsewhere) sentence.elsewhere = run_summary(exec, sentence.program, *elsewhere);
      p.sentences.push_back(std::move(sentence));
    }
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace

DefineOutcome define(Naturalizer& nat, kernel::Session& s, const DefineCall& call) {
  s.begin_call();
  const kernel::InputLimits& limits = s.options().input;
  check_length(limits, call.head, "the head");
  if (call.body.size() > limits.max_body_lines)
    throw sdk::Error(sdk::codes::kInputTooLong, "the body has " + std::to_string(call.body.size()) +
                                                    " lines; the limit is input.max_body_lines = " +
                                                    std::to_string(limits.max_body_lines));
  for (std::size_t i = 0; i < call.body.size(); ++i)
    check_length(limits, call.body[i], "body line " + std::to_string(i + 1));
  if (call.programs.size() > call.body.size())
    throw sdk::Error(sdk::codes::kBadRequest,
                     "the definition has " + std::to_string(call.programs.size()) +
                         " line programs for " + std::to_string(call.body.size()) + " body lines");
  for (int r : call.ranks)
    if (r < 0 || r > kMaxRank)
      throw sdk::Error(
          sdk::codes::kBadRequest,
          "field 'ranks' must be a list of integers from 0 to 1000000, got " + std::to_string(r));
  DefineRequest d;
  d.user = s.user();
  d.head = call.head;
  d.body = call.body;
  d.body_ranks = call.ranks;
  d.body_programs = call.programs;
  const DeadlineExecution exec(s.executor(), s.request_stop());
  d.before = &s.world();
  d.exec = &exec;
  d.stop = s.request_stop();
  d.dry_run = call.dry_run || call.preview;
  d.drop = call.drop;
  DefineOutcome out = nat.define(d);
  if (call.preview) {
    if (auto other = perturbed_worlds(s.world(), 1); !other.empty())
      out.preview_elsewhere = std::move(other.front());
    out.previews = preview_rules(s, exec, out.rules, call.head, out.preview_elsewhere);
  }
  s.emit(RulesDefined{s, call, out});
  return out;
}

std::vector<RuleListing> list_rules(Naturalizer& nat, kernel::Session& s,
                                    const std::optional<std::string>& author) {
  s.begin_call();
  nat.refresh();
  return nat.rules(s.user(), author);
}

void delete_rule(Naturalizer& nat, kernel::Session& s, const std::string& id) {
  s.begin_call();
  nat.delete_rule(s.user(), id);
}

namespace {

// docs/protocol.md § define: `body` lines are utterances or {"text", "formula"} objects, the
// formula (core-language text, as a query answers it) naming the line's reading.
void read_body(const kernel::Json& req, DefineCall& call) {
  const char* what = "a list of utterances or {\"text\", \"formula\"} objects";
  const kernel::Json& body = kernel::request::require(req, "body", what);
  if (!body.is_array())
    throw sdk::Error(sdk::codes::kBadRequest, std::string("field 'body' must be ") + what);
  for (const auto& line : body) {
    const std::string n = std::to_string(call.body.size() + 1);
    if (line.is_string()) {
      call.body.push_back(line.get<std::string>());
      continue;
    }
    if (!line.is_object() || !line.contains("text") || !line["text"].is_string() ||
        !line.contains("formula") || !line["formula"].is_string())
      throw sdk::Error(sdk::codes::kBadRequest, "body line " + n + " must be an utterance or " +
                                                    "an object with string fields 'text' and " +
                                                    "'formula'");
    call.body.push_back(line["text"].get<std::string>());
    call.programs.resize(call.body.size());
    try {
      call.programs.back() = sdk::read_canonical(line["formula"].get<std::string>());
    } catch (const sdk::Error& e) {
      throw sdk::Error(e.code(), "body line " + n + ": the formula does not read: " + e.what());
    }
  }
}

// docs/protocol.md § define, `preview`: each rule's example sentences with their plan summary,
// and the perturbed check.
void write_preview(toolkit::json::JsonWriter& a, const DefineOutcome& out,
                   const kernel::Config& config) {
  a.key("preview").begin_array();
  for (std::size_t i = 0; i < out.previews.size() && i < out.rules.size(); ++i) {
    const RulePreview& p = out.previews[i];
    a.begin_object().key("id").string(p.id).key("rule").string(rule_shape(*out.rules[i]));
    a.key("semantics").string(sdk::render(out.rules[i]->sem));
    a.key("sentences").begin_array();
    for (const auto& e : p.sentences) {
      a.begin_object().key("text").string(e.text).key("formula").string(sdk::render(e.program));
      a.key("realizable").boolean(e.plan.realizable);
      a.key("moves").unsigned_integer(e.plan.moves).key("picks").unsigned_integer(e.plan.picks);
      a.key("drops").unsigned_integer(e.plan.drops).key("end");
      if (e.plan.end)
        a.begin_array().integer(e.plan.end->x).integer(e.plan.end->y).end_array();
      else
        a.null();
      a.key("warnings").begin_array();
      for (const auto& w : e.plan.warnings) a.string(w);
      a.end_array();
      if (!e.plan.error.empty()) a.key("error").string(e.plan.error);
      if (out.preview_elsewhere) {
        const PlanSummary& o = e.elsewhere;
        a.key("elsewhere").begin_object().key("realizable").boolean(o.realizable);
        a.key("moves").unsigned_integer(o.moves).key("picks").unsigned_integer(o.picks);
        a.key("drops").unsigned_integer(o.drops).key("end");
        if (o.end)
          a.begin_array().integer(o.end->x).integer(o.end->y).end_array();
        else
          a.null();
        if (!o.error.empty()) a.key("error").string(o.error);
        a.end_object();
      }
      a.end_object();
    }
    a.end_array().end_object();
  }
  a.end_array();
  if (out.preview_elsewhere) {
    const sdk::Cell& robot = out.preview_elsewhere->robot;
    a.key("elsewhere").begin_object().key("robot").begin_array().integer(robot.x).integer(robot.y);
    a.end_array().key("holding").unsigned_integer(out.preview_elsewhere->held.size()).end_object();
  }
  a.key("perturbed").begin_object();
  a.key("checks").integer(config.get(keys::kPerturbedChecks));
  a.key("worlds").integer(out.perturbations).key("passed").integer(out.perturbed_passed);
  a.key("failed").begin_array();
  for (const auto& f : out.perturbed_failed) a.string(f);
  a.end_array().end_object();
}

// docs/protocol.md § define: {"rules":[rule...],"generalized"[,"discarded"]}.
void op_define(Naturalizer& nat, kernel::Session& s, const kernel::Json& req,
               toolkit::json::JsonWriter& a) {
  DefineCall call;
  call.head = kernel::request::require_string(req, "head", "the utterance to define");
  read_body(req, call);
  if (req.contains("ranks") && !req["ranks"].is_null()) {
    if (!req["ranks"].is_array())
      throw sdk::Error(sdk::codes::kBadRequest, "field 'ranks' must be a list of integers");
    for (const auto& r : req["ranks"]) {
      // get<int> would wrap a large rank into a small (even valid) one.
      if (!r.is_number_integer() || r < 0 || r > kMaxRank)
        throw sdk::Error(
            sdk::codes::kBadRequest,
            "field 'ranks' must be a list of integers from 0 to 1000000, got " + r.dump());
      call.ranks.push_back(r.get<int>());
    }
  }
  if (req.contains("dry_run") && !req["dry_run"].is_null()) {
    if (!req["dry_run"].is_boolean())
      throw sdk::Error(sdk::codes::kBadRequest, "field 'dry_run' must be true or false");
    call.dry_run = req["dry_run"].get<bool>();
  }
  if (req.contains("preview") && !req["preview"].is_null()) {
    if (!req["preview"].is_boolean())
      throw sdk::Error(sdk::codes::kBadRequest, "field 'preview' must be true or false");
    call.preview = req["preview"].get<bool>();
  }
  if (req.contains("drop") && !req["drop"].is_null()) {
    const char* what = "field 'drop' must be a list of preview rule ids (\"new1\", ...)";
    if (!req["drop"].is_array() || req["drop"].size() > 1000)
      throw sdk::Error(sdk::codes::kBadRequest, what);
    for (const auto& id : req["drop"]) {
      if (!id.is_string()) throw sdk::Error(sdk::codes::kBadRequest, what);
      call.drop.push_back(id.get<std::string>());
    }
  }
  const DefineOutcome out = define(nat, s, call);
  a.key("rules").begin_array();
  for (const auto& r : out.rules) write_rule(a, *r);
  a.end_array();
  // Only when there is something to say: answers without conflicts stay as recorded studies
  // hashed them (docs/studio.md §7).
  if (!out.stored) a.key("stored").boolean(false);
  if (!out.held.empty()) a.key("held").string(out.held);
  if (!out.dropped.empty()) {
    a.key("dropped").begin_array();
    for (const auto& id : out.dropped) a.string(id);
    a.end_array();
  }
  if (call.preview) write_preview(a, out, s.runtime().config);
  if (!out.conflicts.empty()) {
    a.key("conflicts").begin_array();
    for (const auto& c : out.conflicts) {
      a.begin_object().key("phrase").string(c.phrase).key("user").string(c.user);
      a.key("kind").string(c.kind).key("before").string(c.before).key("after").string(c.after);
      a.key("readings_before").unsigned_integer(c.readings_before);
      a.key("readings_after").unsigned_integer(c.readings_after).end_object();
    }
    a.end_array();
  }
  a.key("generalized");
  if (out.generalized)
    a.string(sdk::render(out.generalized));
  else
    a.null();
  if (out.generalization_ran) {
    a.key("discarded").begin_array();
    for (const auto& c : out.discarded) {
      a.begin_object().key("formula").string(c.program ? sdk::render(c.program) : std::string());
      a.key("rewriting").string(c.rewriting).key("reason").string(c.reason).end_object();
    }
    a.end_array();
  }
}

// docs/protocol.md § rules: each rule with "head", "body", "uses", "uses_by_author/others".
void op_rules(Naturalizer& nat, kernel::Session& s, const kernel::Json& req,
              toolkit::json::JsonWriter& a) {
  const auto author = kernel::request::optional_string(req, "author", "a user name");
  a.key("rules").begin_array();
  for (const auto& l : list_rules(nat, s, author)) {
    write_rule(a, *l.rule, false);
    a.key("head").string(l.rule->head).key("body").begin_array();
    for (const auto& line : l.rule->body) a.string(line);
    a.end_array().key("uses").unsigned_integer(l.uses_by_author + l.uses_by_others);
    a.key("uses_by_author").unsigned_integer(l.uses_by_author);
    a.key("uses_by_others").unsigned_integer(l.uses_by_others).end_object();
  }
  a.end_array();
}

}  // namespace

void install_naturalization(kernel::Session& session, const std::shared_ptr<Naturalizer>& nat) {
  session.install(std::make_shared<NaturalizationExtension>(nat));
}

std::shared_ptr<Naturalizer> install_naturalization(kernel::Session& session,
                                                    std::shared_ptr<kernel::Runtime> runtime) {
  NaturalizeOptions options = NaturalizeOptions::from_config(runtime->config);
  auto nat = std::make_shared<Naturalizer>(std::move(runtime), std::move(options));
  install_naturalization(session, nat);
  return nat;
}

void NaturalizationExtension::attach(kernel::Session& session) {
  auto nat = naturalizer_;
  session.set_op("define", [nat](kernel::Session& s, const kernel::Json& r,
                                 toolkit::json::JsonWriter& a) { op_define(*nat, s, r, a); });
  session.set_op("rules", [nat](kernel::Session& s, const kernel::Json& r,
                                toolkit::json::JsonWriter& a) { op_rules(*nat, s, r, a); });
  session.set_op("delete_rule",
                 [nat](kernel::Session& s, const kernel::Json& r, toolkit::json::JsonWriter& a) {
                   const std::string id = kernel::request::require_string(r, "rule", "a rule id");
                   naturalization::delete_rule(*nat, s, id);
                   a.key("deleted").string(id);
                 });
  // Every parse sees the rules and deletions other processes committed before it.
  session.on<kernel::QueryBegins>([nat](const kernel::QueryBegins&) { nat->refresh(); });
  if (nat->options().sharing != Sharing::shared)
    session.on<kernel::VisibilityAsked>([nat](const kernel::VisibilityAsked& e) {
      e.filter = [nat, user = e.user](const sdk::Rule& rule) { return nat->visible(rule, user); };
    });
  // A repair's known words include the words of the rules this user sees.
  // The words are a hint: a lexicon that cannot be listed now adds none (the query stands).
  session.on<VocabularyAsked>([nat, &session](const VocabularyAsked& e) {
    try {
      for (const auto& l : list_rules(*nat, session, std::nullopt))
        for (const auto& symbol : l.rule->rhs)
          if (symbol.type == sdk::Symbol::Type::token) e.words.push_back(symbol.text);
    } catch (const sdk::Error&) {
    }
  });
  session.on<kernel::Accepting>(
      [nat](const kernel::Accepting& e) { nat->on_accept(e.user, e.candidate.induced_rules); });
  // A session may have asked on another kernel (a server's pool, docs/studio.md §5): an accept
  // must count and learn against everything committed so far, like a parse.
  session.on<kernel::Activated>([nat](const kernel::Activated&) { nat->refresh(); });
}

}  // namespace flipper::naturalization

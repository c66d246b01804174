// The query and accept ops: parse, rank, plan every shown candidate, learn from the choice.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/kernel/protocol.hpp"
#include "flipper/kernel/session.hpp"
#include "flipper/kernel/session_request.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::kernel {

using toolkit::json::JsonWriter;

namespace {

// Code points, not bytes: the limit is about what a person typed.
std::size_t utf8_length(std::string_view s) {
  std::size_t n = 0;
  for (unsigned char c : s) n += (c & 0xC0) != 0x80;
  return n;
}

std::vector<double> softmax(const std::vector<sdk::Candidate>& candidates) {
  std::vector<double> p(candidates.size());
  if (p.empty()) return p;
  double top = candidates.front().score;
  for (const auto& c : candidates) top = std::max(top, c.score);
  double sum = 0;
  for (std::size_t i = 0; i < p.size(); ++i) sum += p[i] = std::exp(candidates[i].score - top);
  for (double& v : p) v /= sum;
  return p;
}

// The derivation a candidate is credited to: a core-only one when the program has one (that is
// why it ranks as core), else the best.
sdk::DerivationPtr credited_derivation(const sdk::Candidate& c) {
  if (c.derivations.empty()) return nullptr;
  if (c.core_only)
    for (const auto& d : c.derivations)
      if (d->core_only) return d;
  return c.derivations.front();
}

void collect_induced(const sdk::DerivationPtr& d, std::vector<sdk::RulePtr>& out) {
  if (!d) return;
  if (d->rule && d->rule->induced &&
      std::none_of(out.begin(), out.end(),
                   [&](const sdk::RulePtr& r) { return r->id == d->rule->id; }))
    out.push_back(d->rule);
  for (const auto& kid : d->kids) collect_induced(kid, out);
}

}  // namespace

// docs/architecture.md §4: every parse of a session, the query's and its extensions', sees the
// same scorer, rules and limits.
sdk::ParseResult Session::parse(const std::vector<std::string>& tokens, bool want_chart,
                                const char* stage) {
  sdk::ParseRequest pr;
  pr.tokens = tokens;
  pr.context.tokens = &tokens;
  pr.context.user = user_;
  pr.context.usage = runtime_->usage.get();
  pr.scorer = runtime_->scorer.borrow();  // the parser's call guards its scorer calls
  const auto visible = visible_rules();   // outlives the parse below
  pr.visible = sdk::RuleFilter::of(visible);
  pr.beam = options_.beam;
  pr.stop = request_stop();
  pr.want_chart = want_chart;
  sdk::ParseResult result = checked_parse(runtime_->parser, pr);  // docs/plugins-untrusted.md
  if (result.stopped) check_deadline(stage);
  return result;
}

void Session::check_length(std::string_view text) const {
  const std::size_t n = utf8_length(text);
  if (n > options_.max_chars)
    throw sdk::Error(sdk::codes::kInputTooLong, "the utterance has " + std::to_string(n) +
                                                    " characters; the limit is input.max_chars = " +
                                                    std::to_string(options_.max_chars));
}

QueryResult Session::query(const QueryRequest& request) {
  const auto t0 = std::chrono::steady_clock::now();
  begin_call();
  events_.emit(QueryBegins{*this, request.text});
  const std::int64_t k = request.k.value_or(options_.k);
  if (k < 0) throw sdk::Error(sdk::codes::kBadRequest, "field 'k' must not be negative");
  check_length(request.text);

  auto q = std::make_shared<LastQuery>();
  q->text = request.text;
  q->user = user_;
  std::vector<std::string> tokens = sdk::tokenize(q->text);
  auto semicolons = std::count(tokens.begin(), tokens.end(), ";");
  if (semicolons >= options_.max_semicolons)
    throw sdk::Error(sdk::codes::kInputTooLong,
                     "the utterance has " + std::to_string(semicolons) +
                         " ';' tokens; the limit is input.max_semicolons = " +
                         std::to_string(options_.max_semicolons) + " (refused at that many)");
  if (tokens.size() > options_.input.max_tokens)
    throw sdk::Error(sdk::codes::kInputTooLong, "the utterance has " +
                                                    std::to_string(tokens.size()) +
                                                    " tokens; the limit is input.max_tokens = " +
                                                    std::to_string(options_.input.max_tokens));
  q->tokens = std::move(tokens);
  q->parse = parse(q->tokens, false, "parsing");
  q->probs = softmax(q->parse.candidates);
  q->world = world_;

  const auto& cands = q->parse.candidates;
  const std::size_t shown = std::min<std::size_t>(static_cast<std::size_t>(k), cands.size());
  q->shown.reserve(shown);
  for (std::size_t i = 0; i < shown; ++i) {
    ShownCandidate sc;
    sc.index = i;
    sc.derivation = credited_derivation(cands[i]);
    collect_induced(sc.derivation, sc.induced_rules);
    sc.outcome = executor_.run(cands[i].program, world_, request_stop());
    // A candidate cut by a time limit (the request's, or execution's) cannot be shown: the whole
    // query is refused rather than answered differently (docs/core-language.md §9).
    if (sc.outcome.error_code == sdk::codes::kDeadlineExceeded) {
      check_deadline("executing");
      throw sdk::StoppedError(sc.outcome.stopped, "deadline exceeded while executing candidate " +
                                                      std::to_string(i) + ": " +
                                                      sc.outcome.error.value_or("(no message)"));
    }
    if (sc.outcome.error) sc.error_code = sc.outcome.error_code.value_or(sdk::codes::kExecution);
    q->shown.push_back(std::move(sc));
  }

  check_deadline("writing the answer");
  QueryResult result;
  if (!cands.empty())
    result.status =
        std::any_of(cands.begin(), cands.end(), [](const sdk::Candidate& c) { return c.core_only; })
            ? "core"
            : "induced";
  last_query_ = q;
  result.query = std::move(q);
  result.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  events_.emit(QueryAnswered{*this, result});
  return result;
}

// docs/protocol.md § query: {"status","candidates":[{"rank","score","prob","formula","induced",
// "rules","authors","realizable","trace","world","warnings"[,"error"]}],"total","ms"}.
void Session::op_query(const Json& req, JsonWriter& a) {
  QueryRequest request;
  request.text = request::require_string(req, "text", "the utterance to parse");
  request.k = request::optional_int(req, "k", "how many candidates to show");
  const std::shared_ptr<LastQuery> before = last_query_;
  const QueryResult result = query(request);
  const LastQuery& q = *result.query;
  const int dims = q.world.geometry ? q.world.geometry->dims() : 2;
  a.key("status").string(result.status).key("candidates").begin_array();
  for (const ShownCandidate& sc : q.shown) {
    const sdk::Candidate& c = q.parse.candidates[sc.index];
    a.begin_object();
    a.key("rank").unsigned_integer(sc.index);
    a.key("score").number(c.score).key("prob").number(q.probs[sc.index]);
    a.key("formula").string(sdk::render(c.program)).key("induced").boolean(!c.core_only);
    a.key("rules").begin_array();
    for (const auto& r : sc.induced_rules) a.string(r->id);
    a.end_array().key("authors").begin_array();
    std::vector<const std::string*> authors;
    for (const auto& r : sc.induced_rules)
      if (std::none_of(authors.begin(), authors.end(),
                       [&](const std::string* s) { return *s == r->author; })) {
        authors.push_back(&r->author);
        a.string(r->author);
      }
    a.end_array().key("realizable").boolean(sc.outcome.realizable && !sc.outcome.error);
    a.key("trace");
    protocol::append_trace_text(a.raw_begin(), sc.outcome.trace, dims);
    write_changed_world(a.key("world"), sc.outcome.world);
    a.key("warnings").begin_array();
    for (const auto& w : sc.outcome.warnings) a.string(w);
    a.end_array();
    if (sc.error_code) {
      a.key("error").begin_object().key("code").string(*sc.error_code);
      a.key("message").string(sc.outcome.error.value_or("")).end_object();
    }
    a.end_object();
  }
  a.end_array().key("total").unsigned_integer(result.total()).key("ms").number(result.ms);
  try {
    events_.emit(QueryWriting{*this, req, result, a});
  } catch (...) {
    last_query_ = before;  // a refusal leaves the state as it was
    throw;
  }
  write_world_version(a, q.world);
}

AcceptResult Session::accept(const AcceptRequest& request,
                             const std::function<void(const sdk::Outcome&)>& before_commit) {
  begin_call();
  const std::int64_t rank = request.rank;
  if (!last_query_)
    throw sdk::Error(session_codes::kNoQuery, "there is no query to accept a candidate of");
  const LastQuery& q = *last_query_;
  if (rank < 0 || static_cast<std::size_t>(rank) >= q.shown.size())
    throw sdk::Error(session_codes::kRankOutOfRange,
                     "rank " + std::to_string(rank) + " is out of range: the last query showed " +
                         std::to_string(q.shown.size()) + " candidate(s)");
  const ShownCandidate& sc = q.shown[static_cast<std::size_t>(rank)];
  if (sc.error_code)
    throw sdk::Error(session_codes::kNotAcceptable,
                     "candidate " + std::to_string(rank) +
                         " cannot be accepted: its execution failed (" +
                         sc.outcome.error.value_or(*sc.error_code) + ")");
  AcceptResult result;
  // The execution the query showed, not run again (docs/protocol.md, accept): the world is still
  // the query's (a new world discards the last query), and what the user previewed is applied.
  const sdk::Outcome& outcome = result.outcome = sc.outcome;
  if (before_commit) before_commit(outcome);  // the answer: nothing may fail after the commit

  // Nothing is applied unless everything commits: learning and counters are undone when the
  // scorer or the persistence hook (the lexicon transaction) fails, and the world and the last
  // query change only after both succeeded, so a retry applies the accept exactly once.
  // A scorer that reports its changes (sdk::IncrementalScorer) undoes exactly those; any other
  // is saved whole beforehand.
  auto* incremental = dynamic_cast<sdk::IncrementalScorer*>(runtime_->scorer.borrow());
  const bool persisted = events_.has<Accepting>();
  const std::string scorer_before =
      persisted && incremental == nullptr
          ? runtime_->scorer.call("save_state", [](const sdk::Scorer& s) { return s.save_state(); })
          : std::string();
  UsageTable& usage = *runtime_->usage;
  auto count = [&](std::int64_t delta) {
    for (const auto& rule : sc.induced_rules) usage.add(rule->id, rule->author == user_, delta);
  };
  bool counted = false;
  try {
    sdk::ScoreContext ctx;
    ctx.tokens = &q.tokens;
    ctx.user = user_;
    ctx.usage = &usage;
    checked_learn(runtime_->scorer, q.parse.candidates, sc.index, ctx, request_stop());
    count(+1);
    counted = true;
    events_.emit(Accepting{*this, q, static_cast<std::size_t>(rank), sc, outcome, user_});
  } catch (...) {
    if (counted) count(-1);
    if (incremental != nullptr)
      runtime_->scorer.call("discard_changes",
                            [&](sdk::Scorer&) { incremental->discard_changes(); });
    else if (persisted)
      runtime_->scorer.call("load_state", [&](sdk::Scorer& s) { s.load_state(scorer_before); });
    throw;
  }
  if (incremental != nullptr)
    runtime_->scorer.call("commit_changes", [&](sdk::Scorer&) { incremental->commit_changes(); });

  world_ = outcome.world;
  if (events_.has<PlanAccepted>()) {  // after the commit: the accept stands
    const std::string formula = sdk::render(q.parse.candidates[sc.index].program);
    events_.emit(PlanAccepted{q.world, outcome, formula, user_, ++accepted_plans_});
  }
  // The query is consumed: accepting again would apply it twice.
  last_query_.reset();
  return result;
}

// docs/protocol.md § accept: {"world","trace","warnings"} (protocol 2: "world_version" first).
void Session::op_accept(const Json& req, JsonWriter& a) {
  AcceptRequest request;
  request.rank = request::require_int(req, "rank", "index into the last query's candidates",
                                      session_codes::kRankOutOfRange);
  accept(request, [&](const sdk::Outcome& outcome) {
    const int dims = outcome.world.geometry ? outcome.world.geometry->dims() : 2;
    write_world_version(a, outcome.world);
    write_changed_world(a.key("world"), outcome.world);
    a.key("trace");
    protocol::append_trace_text(a.raw_begin(), outcome.trace, dims);
    a.key("warnings").begin_array();
    for (const auto& w : outcome.warnings) a.string(w);
    a.end_array();
  });
}

}  // namespace flipper::kernel

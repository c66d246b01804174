// The replay driver: one kernel Session per run, commands in log order (see replayer.hpp).
#include "flipper/replay/replayer.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include "flipper/corpus/accept_diff.hpp"
#include "flipper/corpus/original_formula.hpp"
#include "flipper/corpus/original_text.hpp"
#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/kernel/session.hpp"
#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/naturalization/repair_extension.hpp"
#include "flipper/replay/deletion_map.hpp"
#include "flipper/replay/rule_oracle.hpp"
#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/wiring/session_factory.hpp"

namespace flipper::replay {
namespace {

// Words a derivation leaves out (any parser): its span minus the tokens its rules consume.
int words_left_out(const sdk::Derivation& d) {
  int consumed = 0;
  auto walk = [&](const sdk::Derivation& n, auto& self) -> void {
    for (const auto& s : n.rule->rhs) consumed += s.type != sdk::Symbol::Type::category;
    for (const auto& k : n.kids) self(*k, self);
  };
  walk(d, walk);
  return d.end - d.start - consumed;
}

std::string strip_spaces(std::string s) {
  s.erase(std::remove_if(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c); }),
          s.end());
  return s;
}

// Robot cell, carried items (multiset) and items on the floor (multiset), for comparing worlds
// after an accept: item ids and list order are not part of the comparison.
struct WorldDigest {
  std::pair<long, long> robot{0, 0};
  std::vector<std::pair<std::string, std::string>> held;
  std::vector<std::tuple<long, long, std::string, std::string>> floor;
};

template <class J>
WorldDigest digest(const J& w) {
  WorldDigest d;
  if (w.contains("robot")) {
    const auto& r = w["robot"];
    d.robot = {r.value("x", 0L), r.value("y", 0L)};
    if (r.contains("holding"))
      for (const auto& h : r["holding"])
        d.held.emplace_back(h.value("color", std::string()), h.value("shape", std::string()));
  }
  if (w.contains("items"))
    for (const auto& i : w["items"])
      d.floor.emplace_back(i.value("x", 0L), i.value("y", 0L), i.value("color", std::string()),
                           i.value("shape", std::string()));
  std::sort(d.held.begin(), d.held.end());
  std::sort(d.floor.begin(), d.floor.end());
  return d;
}

// The planner calls made while an accepted program executes (AcceptRow's planner figures): the
// process's plugin-call observer adds each `plan`/`tour` call of a planner to the tally of the
// thread that made it, while a tally is open.
struct PlanTally {
  int calls = 0;
  std::chrono::nanoseconds cpu{0};
};
thread_local PlanTally* g_plan_tally = nullptr;

void tally_planner_call(const kernel::PluginId& plugin, std::string_view op,
                        const kernel::PluginCallTime& time) {
  if (g_plan_tally == nullptr || plugin.kind != "planner" || (op != "plan" && op != "tour")) return;
  ++g_plan_tally->calls;
  g_plan_tally->cpu += time.thread_cpu;
}

// Opens a tally for its lifetime (and the observer, restoring the one before).
class PlanTallyScope {
 public:
  explicit PlanTallyScope(PlanTally& tally)
      : previous_(kernel::set_plugin_call_observer(&tally_planner_call)) {
    g_plan_tally = &tally;
  }
  ~PlanTallyScope() {
    g_plan_tally = nullptr;
    kernel::set_plugin_call_observer(previous_);
  }
  PlanTallyScope(const PlanTallyScope&) = delete;
  PlanTallyScope& operator=(const PlanTallyScope&) = delete;

 private:
  kernel::PluginCallObserver previous_;
};

// Path length (moves) and turns (a move in another direction than the move before) of a trace
// that starts at `start`; picks and drops do not break a straight line.
std::pair<int, int> path_shape(const sdk::Cell& start, const std::vector<sdk::TraceStep>& trace) {
  int moves = 0, turns = 0;
  sdk::Cell at = start;
  std::optional<sdk::Cell> heading;
  for (const auto& step : trace) {
    if (step.act != sdk::TraceStep::Act::move) continue;
    const sdk::Cell d{step.cell.x - at.x, step.cell.y - at.y, step.cell.z - at.z};
    if (heading && *heading != d) ++turns;
    heading = d;
    at = step.cell;
    ++moves;
  }
  return {moves, turns};
}

// Runs one typed session call; returns "" when it succeeded, else the protocol's error code for
// what it threw (as the session would have answered the request).
template <class F>
std::string attempt(F&& call) {
  try {
    call();
    return {};
  } catch (const sdk::Error& e) {
    return e.code();
  } catch (const std::exception&) {
    return sdk::codes::kInternal;
  }
}

bool is_observation(const std::string& kind) {
  static const std::set<std::string> kKinds = {"live",  "rerun",         "flip",      "undo",
                                               "reset", "task_start",    "task_skip", "goal",
                                               "world", "session_start", "resume",    "page_load"};
  return kKinds.count(kind) != 0;
}

class RunReplay {
 public:
  RunReplay(const Corpus& corpus, const Run& run, const ReplayOptions& options, ReplayResult& out)
      : corpus_(corpus),
        run_(run),
        out_(out),
        reparse_bodies_(options.reparse_bodies),
        repair_(options.repair) {
    std::vector<std::string> sets = mode_overrides(run.group);
    for (auto& k : alignment_overrides(corpus, run)) sets.push_back(std::move(k));
    for (auto& k : view_overrides(corpus, run)) sets.push_back(std::move(k));
    sets.insert(sets.end(), options.sets.begin(), options.sets.end());
    session_ = wiring::open_session(options.config_file, sets);
    naturalization_ = session_->extension<naturalization::NaturalizationExtension>();
    if (naturalization_ == nullptr)
      throw sdk::Error(sdk::codes::kInternal, "replay: the session has no naturalization");
  }

  void preload() {
    if (run_.group != "C") return;
    for (const Definition* d : corpus_.preloaded(run_.source)) {
      DefineRow row{d->def_id, run_.source, d->author(), d->head, true, false,
                    "",        0,           "",          "",      false};
      set_user(d->author());
      define(*d, d->head, d->body, row);
    }
  }

  void command(const Command& c) {
    // A studio recording's observational kinds change nothing a replay reproduces (live checks,
    // re-runs, flips, task marks, world steps whose result the next command's world_id names;
    // docs/studio.md §7).
    if (is_observation(c.kind)) return;
    if (c.kind != "q" && c.kind != "accept") last_qid_.clear();  // defines/deletes change parses
    set_user(c.user);
    set_world(c.world_id);
    if (c.kind == "q")
      query(c);
    else if (c.kind == "accept")
      accept(c);
    else if (c.kind == "def" || c.kind == "def_ret" || c.kind == "def_iso")
      define_command(c);
    else if (c.kind == "delete")
      delete_rule(c);
  }

 private:
  void set_user(const std::string& user) {
    if (user == session_->user()) return;
    attempt([&] { session_->set_user(user); });  // an empty name keeps the current user
  }

  // Asks the session again without recording (the accept of another user's query needs it).
  void requery(const std::string& text, std::optional<std::int64_t> k = std::nullopt) {
    attempt([&] { session_->query(kernel::QueryRequest{text, k}); });
  }

  void set_world(const std::string& id) {
    if (id.empty() || id == world_id_) return;
    auto cached = world_cache_.find(id);
    if (cached == world_cache_.end()) {
      auto it = corpus_.worlds.find(id);
      if (it == corpus_.worlds.end()) return;  // unknown world: keep the current one
      cached =
          world_cache_.emplace(id, kernel::load_world_file(session_->runtime(), it->second.dump()))
              .first;
    }
    session_->set_world(cached->second);
    world_id_ = id;
  }

  void query(const Command& c) {
    QueryRow row;
    row.qid = c.qid;
    row.run = c.source;
    row.group = c.group;
    row.user = c.user;
    row.phase = c.phase;
    row.utterance = c.utterance;
    row.in_authors_tables = c.in_authors_tables;
    row.tokens = static_cast<int>(sdk::tokenize(c.utterance).size());
    row.original = c.status;
    row.original_author = c.author.value_or("");
    row.original_parses = c.n_parses;
    row.original_ms = c.walltime_s * 1000.0;
    kernel::QueryResult result;
    std::shared_ptr<const naturalization::Repair> repair;
    const kernel::QueryRequest request{c.utterance, {}};
    const bool ok = attempt([&] {
                      result = session_->query(request);
                      if (repair_ && c.status == "Nothing")
                        repair = naturalization::repair_query(*session_, result);
                    }).empty();
    last_qid_ = c.qid;
    if (ok) {
      const kernel::LastQuery& q = *result.query;
      row.ours = result.status;
      row.ms = result.ms;
      row.our_author = "none";
      if (!q.shown.empty() && !q.parse.candidates[q.shown[0].index].core_only &&
          !q.shown[0].induced_rules.empty()) {
        row.our_author = "self";
        for (const auto& rule : q.shown[0].induced_rules)
          if (rule->author != c.user) row.our_author = "other";
      }
      row.our_candidates = static_cast<int>(q.parse.candidates.size());
      const auto& top = q.parse.candidates;
      row.floating =
          !top.empty() && !top[0].derivations.empty() && words_left_out(*top[0].derivations[0]) > 0;
      if (repair)
        for (const auto& near : repair->nearest) {
          row.suggestions.push_back(near.text);
          row.suggestion_formulas.push_back(sdk::render(near.program));
        }
    } else {
      row.ours = "error";
    }
    out_.queries.push_back(std::move(row));
  }

  // The original's candidate that was accepted (its printed text is the accepted program).
  const OriginalAnswer::Candidate* accepted_candidate(const Command& c) const {
    auto it = corpus_.answers.find(c.for_qid);
    if (it == corpus_.answers.end()) return nullptr;
    const auto& cands = it->second.candidates;
    for (const auto& k : cands)
      if (k.formula == c.formula) return &k;
    if (auto r = it->second.accepted_rank; r && *r >= 0 && *r < static_cast<int>(cands.size()))
      return &cands[*r];
    return nullptr;
  }

  void accept(const Command& c) {
    // Users of one run interleave: another user's command may have replaced the session's last
    // query since this user's `q`, so ask it again (same user, same logged world; not recorded).
    if ((last_qid_ != c.for_qid || !session_->last_query()) && !c.utterance.empty()) {
      requery(c.utterance);
      last_qid_ = c.for_qid;
    }
    AcceptRow row;
    row.qid = c.qid;
    row.run = c.source;
    row.group = c.group;
    row.user = c.user;
    const kernel::LastQuery* q = session_->last_query();
    const OriginalAnswer::Candidate* original = accepted_candidate(c);
    if (!q || q->parse.candidates.empty()) {
      row.note = "no candidates";
    } else if (!original) {
      row.note = "accepted formula not in the original's answers";
    } else {
      const std::string text = corpus::normalize_original_pretty(original->pretty);
      sdk::Program program;
      try {
        program = sdk::read_canonical(text);
      } catch (const sdk::Error&) {
        // Unreadable: fall back to rendered-text comparison below.
      }
      const std::string flat = strip_spaces(text);
      const auto& cands = q->parse.candidates;
      for (std::size_t i = 0; i < cands.size() && row.rank < 0; ++i)
        if ((program && sdk::equal(program, cands[i].program)) ||
            strip_spaces(sdk::render(cands[i].program)) == flat)
          row.rank = static_cast<int>(i);
      row.matched = row.rank >= 0;
      if (!row.matched) row.note = "accepted program not among our candidates";
    }
    if (row.matched) execute(c, *original, row);
    out_.accepts.push_back(std::move(row));
  }

  void execute(const Command& c, const OriginalAnswer::Candidate& original, AcceptRow& row) {
    if (row.rank >= static_cast<int>(session_->last_query()->shown.size())) {
      const std::string text = session_->last_query()->text;  // copy: re-querying replaces it
      requery(text, row.rank + 1);
    }
    // What the classification needs, before the accept consumes the query: the shown
    // candidate's outcome is the execution the accept commits (same program, same world).
    const kernel::LastQuery& q = *session_->last_query();
    const sdk::Outcome outcome = q.shown[static_cast<std::size_t>(row.rank)].outcome;
    const sdk::WorldState start = q.world;
    const sdk::Program program = q.parse.candidates[static_cast<std::size_t>(row.rank)].program;

    kernel::AcceptResult accepted;
    PlanTally tally;
    // The planner's figures of the program: an accept plans nothing (it applies the query's
    // execution, docs/protocol.md), so the program runs once more for them, unless its execution
    // failed (the accept refuses it without executing, as it always did).
    if (!outcome.error) {
      const PlanTallyScope scope(tally);
      (void)session_->executor().run(program, start);
    }
    const std::string error =
        attempt([&] { accepted = session_->accept(kernel::AcceptRequest{row.rank}); });
    row.executed = error.empty();
    row.plan_calls = tally.calls;
    row.plan_cpu_ms = std::chrono::duration<double, std::milli>(tally.cpu).count();
    row.plan_success = row.executed && accepted.outcome.realizable;
    if (row.executed)
      std::tie(row.path_length, row.turns) = path_shape(start.robot, accepted.outcome.trace);
    if (row.executed) {
      world_id_.clear();  // the session now holds our world, not a logged one
    } else if (error == kernel::session_codes::kNotAcceptable && outcome.error_code) {
      // The candidate's own execution failed (a refused plugin answer: invalid_plan, ...): its
      // code is the reason, its message goes to standard error (docs/plugins-untrusted.md §3).
      row.note = *outcome.error_code;
      std::cerr << "flipper replay: " << c.qid << ": " << row.note << ": "
                << outcome.error.value_or("") << "\n";
    } else {
      row.note = error;
    }
    auto after = corpus_.worlds.find(c.next_world_id);
    if (after == corpus_.worlds.end()) return;
    if (row.executed) {
      row.compared = true;
      const WorldDigest ours = digest(session_->world_json(accepted.outcome.world)),
                        theirs = digest(after->second);
      row.robot = ours.robot == theirs.robot;
      row.held = ours.held == theirs.held;
      row.floor = ours.floor == theirs.floor;
    }
    // Without a logged world before, the world we started from stands in for it (the
    // classification then cannot detect a wrong start).
    auto before = corpus_.worlds.find(c.world_id);
    const nlohmann::json start_json =
        before == corpus_.worlds.end() ? session_->world_json(start) : nlohmann::json();
    const nlohmann::json& before_json =
        before == corpus_.worlds.end() ? start_json : before->second;
    row.diff = corpus::class_id(
        corpus::classify_accept({before_json, after->second, c.next_world_id, program, start,
                                 outcome, original.path.is_array() ? &original.path : nullptr,
                                 session_->runtime().planner.borrow()}));
  }

  static RuleShape shape_of(const sdk::Rule& r) {
    RuleShape shape{r.lhs, {}, sdk::render(r.sem), r.how == sdk::RuleOrigin::alignment};
    for (const auto& symbol : r.rhs) shape.rhs.push_back(symbol.text);
    return shape;
  }

  void define_command(const Command& c) {
    DefineRow row{c.qid, c.source, c.user, c.head, false, false, "", 0, "", "", false};
    auto it = corpus_.definition_index.find(c.def_id);
    if (it != corpus_.definition_index.end())
      define(corpus_.definitions[it->second], c.head, c.body, row);
    else
      define(Definition{}, c.head, c.body, row);
  }

  void define(const Definition& def, const std::string& head, const std::vector<BodyLine>& body,
              DefineRow& row) {
    naturalization::DefineCall call;
    call.head = head;
    for (const auto& b : body) call.body.push_back(b.utterance);
    // A studio line without a formula names the reading chosen by rank (docs/studio.md §7).
    if (std::any_of(body.begin(), body.end(), [](const BodyLine& b) { return b.rank > 0; }))
      for (const auto& b : body) call.ranks.push_back(std::max(0, b.rank));
    naturalization::DefineOutcome defined;
    // The rules the author sees before the definition: the original's rules we do not induce
    // again may already be there (rule_oracle.hpp classify_rules, "present").
    std::vector<RuleShape> present;
    if (!def.def_id.empty()) {
      (void)attempt([&] {
        for (const auto& l : naturalization_->rules(*session_, std::nullopt))
          present.push_back(shape_of(*l.rule));
      });
    }
    row.error_code = attempt([&] {
      // The program the user accepted for each line, as the 2018 server induced from it
      // (ReplayOptions::reparse_bodies); a line without one is parsed.
      for (const auto& b : body)
        call.programs.push_back(reparse_bodies_ || b.formula.empty() || b.formula == "()"
                                    ? nullptr
                                    : corpus::read_formula(b.formula));
      defined = naturalization_->define(*session_, call);
    });
    row.ok = row.error_code.empty();
    std::vector<OurRule> ours;
    std::vector<RuleShape> shapes;
    if (row.ok)
      for (const auto& r : defined.rules) {
        ours.push_back({r->id, sdk::to_string(r->how)});
        shapes.push_back(shape_of(*r));
      }
    row.rules = static_cast<int>(ours.size());
    row.rule_match = compare_rules(def.rules, shapes);
    const RuleIdentity identity = classify_rules(def.rules, shapes, present);
    row.rule_identity = identity.cls;
    row.action_hole = identity.action_hole;
    // Definitions not in definitions.jsonl have no logged rules: they only take part in the
    // deletion model as empty entries.
    if (!def.def_id.empty()) {
      auto& ids = rules_by_definition_[def.def_id];
      for (const auto& r : ours) ids.push_back(r.id);
    }
    if (!def.def_id.empty() && corpus_.definition_index.count(def.def_id))
      deletions_.add_definition(def, session_->user(), std::move(ours));
    out_.defines.push_back(std::move(row));
  }

  void delete_rule(const Command& c) {
    DeleteRow row{c.qid, c.source, c.user, c.rule_index, "", {}, ""};
    // A studio recording names the rule by its define and position: delete our rule there.
    if (auto it = rules_by_definition_.find(c.def_id);
        it != rules_by_definition_.end() && c.rule_pos >= 0) {
      row.definition = c.def_id;
      if (c.rule_pos < static_cast<int>(it->second.size())) {
        const std::string id = it->second[static_cast<std::size_t>(c.rule_pos)];
        const std::string error = attempt([&] { naturalization_->delete_rule(*session_, id); });
        if (error.empty())
          row.deleted.push_back(id);
        else
          row.note = id + ": " + error;
      } else {
        row.note = "our definition has no rule " + std::to_string(c.rule_pos);
      }
      out_.deletes.push_back(std::move(row));
      return;
    }
    DeletionMap::Mapping m = deletions_.map(c.user, c.rule_index);
    row.definition = m.def_id;
    row.note = m.note;
    for (const auto& id : m.ids) {
      const std::string error = attempt([&] { naturalization_->delete_rule(*session_, id); });
      if (error.empty())
        row.deleted.push_back(id);
      else
        row.note += (row.note.empty() ? "" : "; ") + id + ": " + error;
    }
    out_.deletes.push_back(std::move(row));
  }

  const Corpus& corpus_;
  const Run& run_;
  ReplayResult& out_;
  std::unique_ptr<kernel::Session> session_;
  naturalization::NaturalizationExtension* naturalization_ =
      nullptr;  ///< the session's define/delete service
  bool reparse_bodies_;
  bool repair_;
  std::string last_qid_;  ///< the `q` the session's last query answers
  std::string world_id_;  ///< the logged world the session holds ("" after our own accept)
  std::unordered_map<std::string, sdk::WorldState> world_cache_;
  DeletionMap deletions_;
  std::unordered_map<std::string, std::vector<std::string>> rules_by_definition_;  ///< our ids
};

// The commands of a run that --max-queries keeps.
std::size_t kept_commands(const Corpus& corpus, const Run& run, int max_queries) {
  if (max_queries <= 0) return run.commands.size();
  int queries = 0;
  for (std::size_t i = 0; i < run.commands.size(); ++i)
    if (corpus.commands[run.commands[i]].kind == "q" && ++queries > max_queries) return i;
  return run.commands.size();
}

}  // namespace

std::vector<std::string> mode_overrides(const std::string& group) {
  const char* sharing = group == "A" ? "core" : group == "B" ? "private" : "shared";
  return {"lexicon.path=:memory:", std::string("lexicon.sharing=") + sharing,
          "lexicon.preload=", "induction.alignment=false"};
}

namespace {
// Whether some definition of `run` logged a rule that `pred` holds for.
template <class Pred>
bool run_logged_rule(const Corpus& corpus, const Run& run, Pred pred) {
  return std::any_of(
      corpus.definitions.begin(), corpus.definitions.end(), [&](const Definition& d) {
        return d.source == run.source && std::any_of(d.rules.begin(), d.rules.end(), pred);
      });
}
}  // namespace

std::vector<std::string> alignment_overrides(const Corpus& corpus, const Run& run) {
  // A 2018 log's rule has the original's formula, no `semantics` in our notation (a studio
  // recording's has: those runs keep the keys mode_overrides gives).
  if (!run_logged_rule(corpus, run,
                       [](const LoggedRule& r) { return r.alignment && r.semantics.empty(); }))
    return {};
  return {"induction.alignment=true", "induction.alignment_mode=window"};
}

std::vector<std::string> view_overrides(const Corpus& corpus, const Run& run) {
  if (!run_logged_rule(corpus, run, [](const LoggedRule& r) { return r.semantics.empty(); }))
    return {};
  return {"induction.view=everyone"};
}

std::vector<const Run*> select_runs(const Corpus& corpus, const std::vector<std::string>& names) {
  std::vector<const Run*> runs;
  if (names.empty()) {
    for (const auto& r : corpus.runs) runs.push_back(&r);
    return runs;
  }
  for (const auto& name : names) {
    const Run* r = corpus.find_run(name);
    if (!r) {
      std::string known;
      for (const auto& k : corpus.runs) known += (known.empty() ? "" : ", ") + k.source;
      throw sdk::Error(sdk::codes::kBadRequest, "unknown run '" + name + "' in corpus " +
                                                    corpus.dir + " (runs: " + known + ")");
    }
    runs.push_back(r);
  }
  return runs;
}

ReplayResult replay(const Corpus& corpus, const ReplayOptions& options) {
  const std::vector<const Run*> runs = select_runs(corpus, options.runs);
  std::size_t total = 0, done = 0;
  for (const Run* r : runs) total += kept_commands(corpus, *r, options.max_queries);

  ReplayResult out;
  for (const Run* r : runs) {
    out.runs.push_back(r->source);
    RunReplay rr(corpus, *r, options, out);
    rr.preload();
    const std::size_t n = kept_commands(corpus, *r, options.max_queries);
    for (std::size_t i = 0; i < n; ++i) {
      rr.command(corpus.commands[r->commands[i]]);
      if (options.progress) options.progress(++done, total, r->source);
    }
  }
  return out;
}

}  // namespace flipper::replay

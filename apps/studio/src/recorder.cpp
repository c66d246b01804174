#include "recorder.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "flipper/corpus/answer_digest.hpp"
#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/record/checksum.hpp"
#include "flipper/record/durable_file.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/version.hpp"
#include "json_file.hpp"
#include "registry.hpp"
#include "study.hpp"

namespace flipper::studio {
namespace fs = std::filesystem;
using kernel::Json;

namespace {

std::string now_iso() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::ostringstream s;
  s << std::put_time(&tm, "%Y-%m-%dT%H:%M:%S") << '.' << std::setw(3) << std::setfill('0') << ms;
  return s.str();
}

// The original system's status words (docs/protocol.md status -> corpus status).
std::string corpus_status(const std::string& status) {
  if (status == "core") return "Core";
  if (status == "induced") return "Induced";
  return "Nothing";
}

record::AppendFile open_append(const fs::path& path) {
  try {
    return record::AppendFile(path.string());
  } catch (const sdk::Error& e) {
    throw sdk::Error(sdk::codes::kBadConfig, std::string("study: ") + e.what());
  }
}

template <class F>
void for_each_json_line(const fs::path& path, F&& f) {
  std::ifstream in(path);
  std::string text;
  while (std::getline(in, text)) {
    if (text.empty()) continue;
    const Json j = Json::parse(text, nullptr, false);
    f(j);
  }
}

// One whole line of a .jsonl file, or write_failed and the file as it was (Json or
// ordered_json: queries.jsonl keeps its members in reading order).
template <class J>
void append_line(record::AppendFile& out, const J& line) {
  out.append(line.dump(-1, ' ', false, J::error_handler_t::replace) + "\n");
}

std::string member_text(const Json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// Milliseconds since `start`, whole (a participant's time on a task, not a budget).
std::int64_t since_ms(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() -
                                                               start)
      .count();
}

const std::vector<std::string> kCounted = {"q",   "live",   "accept", "reject",
                                           "def", "delete", "undo",   "reset"};

}  // namespace

const std::vector<std::string>& Recorder::files() {
  static const std::vector<std::string> kFiles = {
      "queries.jsonl",   "worlds.jsonl",    "definitions.jsonl", "original-answers.jsonl",
      "sessions.json",   "exchanges.jsonl", "participants.json", "study.json",
      "preload-C.jsonl", "audit.jsonl"};
  return kFiles;
}

Recorder::Recorder(std::shared_ptr<Study> study,
                   const std::vector<std::pair<std::string, kernel::Config>>& kernels)
    : study_(std::move(study)),
      dir_(study_->record_dir()),
      participants_((fs::path(study_->record_dir()) / "participants.json").string()) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec)
    throw sdk::Error(sdk::codes::kBadConfig,
                     "study: cannot create '" + dir_ + "': " + ec.message());
  load_existing();
  const fs::path dir = dir_;
  queries_ = open_append(dir / "queries.jsonl");
  worlds_ = open_append(dir / "worlds.jsonl");
  definitions_ = open_append(dir / "definitions.jsonl");
  answers_ = open_append(dir / "original-answers.jsonl");
  exchanges_ = open_append(dir / "exchanges.jsonl");
  audit_ = open_append(dir / "audit.jsonl");
  if (!fs::exists(dir / "study.json")) write_study_json(kernels);
  participants_.save();
}

// A recording already there: numbering, worlds, sessions, the rule map and the preload continue
// (docs/studio.md §7 "Restarts").
void Recorder::load_existing() {
  const fs::path dir = dir_;
  for_each_json_line(dir / "queries.jsonl", [&](const Json&) { ++line_; });
  for_each_json_line(dir / "exchanges.jsonl", [&](const Json&) { ++exchange_; });
  for_each_json_line(dir / "worlds.jsonl", [&](const Json& j) {
    if (!j.is_object()) return;
    Json w = j;
    const std::string id = member_text(j, "world_id");
    w.erase("world_id");
    worlds_by_id_[id] = std::move(w);
  });
  for_each_json_line(dir / "definitions.jsonl", [&](const Json& j) {
    if (!j.is_object()) return;
    const std::string source = member_text(j, "source");
    if (member_text(j, "origin") == "preloaded") preloaded_.insert(source);
    int pos = 0;
    for (const auto& r : j.value("induced_rules", Json::array())) {
      rule_defs_[member_text(r, "id")] = {member_text(j, "def_id"), pos++};
      ++rule_lines_[source];
    }
  });
  if (auto s = read_json_file((dir / "sessions.json").string()); s && s->is_array())
    sessions_ = std::move(*s);
}

void Recorder::write_study_json(
    const std::vector<std::pair<std::string, kernel::Config>>& kernels) {
  Json groups = Json::object();
  for (const auto& [group, config] : kernels)
    groups[group] = {{"sharing", sharing_of_group(group)},
                     {"source", study_->source(group)},
                     {"config_source", config.source()},
                     {"config", config.dump()}};
  Json tasks = Json::array();
  for (const auto& t : study_->tasks()) tasks.push_back(t.name);
  std::string preload;
  if (!study_->preload().empty()) {
    std::error_code ec;
    fs::copy_file(study_->preload(), fs::path(dir_) / "preload-C.jsonl",
                  fs::copy_options::overwrite_existing, ec);
    if (!ec) preload = "preload-C.jsonl";
  }
  const auto& v = sdk::kSdkVersion;
  const Json study{{"name", study_->name()},
                   {"started", now_iso()},
                   {"flipper_sdk", std::to_string(v.major) + "." + std::to_string(v.minor) + "." +
                                       std::to_string(v.patch)},
                   {"groups", std::move(groups)},
                   {"tasks", std::move(tasks)},
                   {"preload", preload.empty() ? Json() : Json(preload)}};
  write_json_file((fs::path(dir_) / "study.json").string(), study);
}

void Recorder::write_sessions() {
  write_json_file((fs::path(dir_) / "sessions.json").string(), sessions_);
}

std::optional<ParticipantState> Recorder::participant_of(const std::string& account) {
  std::lock_guard lock(mutex_);
  const ParticipantState* p = participants_.find_account(account);
  return p ? std::optional<ParticipantState>(*p) : std::nullopt;
}

bool Recorder::open() {
  std::lock_guard lock(mutex_);
  return participants_.open();
}

void Recorder::set_open(bool open) {
  std::lock_guard lock(mutex_);
  participants_.set_open(open);
  participants_.save();
}

std::string Recorder::next_id(const std::function<bool(const std::string&)>& taken) {
  std::lock_guard lock(mutex_);
  std::string id = participants_.next_id(taken);
  participants_.save();
  return id;
}

ParticipantState Recorder::enroll(const std::string& account, const std::string& requested) {
  std::lock_guard lock(mutex_);
  if (const ParticipantState* p = participants_.find_account(account)) return *p;
  const auto& groups = study_->groups();
  std::string group = groups[participants_.all().size() % groups.size()];
  if (std::find(groups.begin(), groups.end(), requested) != groups.end()) group = requested;
  ParticipantState s;
  s.participant = account;
  s.account = account;
  s.group = group;
  s.first_seen = s.last_seen = now_iso();
  ParticipantState& added = participants_.add(std::move(s));
  participants_.save();
  return added;
}

std::string Recorder::world_id(const SessionEntry& entry) {
  Json world = entry.session->world_json(entry.session->world());
  std::ostringstream id;
  id << 'w' << std::hex << std::hash<std::string>{}(world.dump());
  if (!worlds_by_id_.count(id.str())) {
    Json line{{"world_id", id.str()}};
    for (const auto& [k, v] : world.items()) line[k] = v;
    append_line(worlds_, line);
    worlds_by_id_.emplace(id.str(), std::move(world));
  }
  return id.str();
}

ParticipantState& Recorder::state(const SessionEntry& entry) {
  ParticipantState* p = participants_.find(entry.participant);
  if (p == nullptr) {  // enrolled before (always, through enroll); kept for safety
    ParticipantState s;
    s.participant = s.account = entry.participant;
    s.group = entry.group;
    p = &participants_.add(std::move(s));
  }
  p->last_seen = now_iso();
  p->last_request = std::chrono::steady_clock::now();
  return *p;
}

Recorder::Line Recorder::line(const SessionEntry& entry, ParticipantState& p,
                              const std::string& kind, std::optional<std::int64_t> exchange) {
  ++line_;
  const std::string source = study_->source(entry.group);
  const auto& tasks = study_->tasks();
  const bool in_task = p.task >= 0 && p.task < static_cast<int>(tasks.size());
  if (std::find(kCounted.begin(), kCounted.end(), kind) != kCounted.end()) ++p.counts[kind];
  // Ordered: who, what and when first (docs/studio.md §7).
  return Line{{"qid", source + "#" + std::to_string(line_)},
              {"kind", kind},
              {"time", now_iso()},
              {"participant", entry.participant},
              {"group", entry.group},
              {"task", p.task},
              {"task_name", in_task ? Line(tasks[static_cast<std::size_t>(p.task)].name) : Line()},
              {"phase", in_task ? "task" : "tutorial"},
              {"exchange", exchange ? Line(*exchange) : Line()},
              {"world_id", p.world_id},
              {"next_world_id", p.world_id},
              {"source", source},
              {"file", "studio"},
              {"line", line_},
              {"cohort", study_->name()},
              {"session", entry.participant},
              {"uid", entry.participant},
              {"account", p.account},
              {"user", entry.session->user()},
              {"in_authors_tables", true},
              {"syntax", "studio"},
              {"seq", ++live_[entry.participant].seq},
              {"split", "studio"}};
}

void Recorder::session_started(const SessionEntry& entry, bool resumed) {
  std::lock_guard lock(mutex_);
  ParticipantState& p = state(entry);
  if (!resumed) p.world_id = world_id(entry);
  preloaded(entry.group);
  Line c = line(entry, p, resumed ? "resume" : "session_start", std::nullopt);
  append_line(queries_, c);
  sessions_.push_back({{"source", study_->source(entry.group)},
                       {"session", entry.participant},
                       {"resumed", resumed},
                       {"time", c["time"]}});
  session_numbers_[entry.token] = sessions_.size() - 1;
  write_sessions();
  participants_.save();
}

Json Recorder::resume_world(const std::string& participant) {
  std::lock_guard lock(mutex_);
  const ParticipantState* p = participants_.find(participant);
  if (p == nullptr) return nullptr;
  auto it = worlds_by_id_.find(p->world_id);
  return it == worlds_by_id_.end() ? Json() : it->second;
}

// Group C's preloaded definitions, written once per recording (docs/studio.md §7).
void Recorder::preloaded(const std::string& group) {
  const std::string source = study_->source(group);
  if (group != "C" || study_->preload().empty() || !preloaded_.insert(source).second) return;
  std::ifstream in(study_->preload());
  std::string text;
  int n = 0;
  while (std::getline(in, text)) {
    const Json d = Json::parse(text, nullptr, false);
    if (!d.is_object()) continue;
    Json body = Json::array();
    for (const auto& b : d.value("body", Json::array()))
      body.push_back({{"utterance", b.is_string() ? b : Json(member_text(b, "text"))},
                      {"formula", b.is_object() ? Json(member_text(b, "formula")) : Json("")}});
    append_line(definitions_, Json{{"def_id", "p:" + source + "#" + std::to_string(++n)},
                                   {"origin", "preloaded"},
                                   {"source", source},
                                   {"group", group},
                                   {"kind", "def"},
                                   {"user", d.value("author", std::string("expert"))},
                                   {"head", d.value("head", std::string())},
                                   {"body", std::move(body)},
                                   {"line", n}});
  }
}

bool Recorder::goal_reached(const SessionEntry& entry, int task) const {
  const auto& tasks = study_->tasks();
  if (task < 0 || task >= static_cast<int>(tasks.size())) return false;
  const TaskGoal& goal = tasks[static_cast<std::size_t>(task)].goal;
  return !goal.empty() && goal.reached(entry.session->world_json(entry.session->world()));
}

void RecorderTap::attach(kernel::Session& session) {
  session.on<kernel::RequestAnswered>([this](const kernel::RequestAnswered& e) {
    heard_.answered = true;
    heard_.code = e.code;
  });
  session.on<kernel::QueryAnswered>([this](const kernel::QueryAnswered& e) {
    const kernel::LastQuery& q = *e.result.query;
    heard_.status = e.result.status;
    heard_.candidates.clear();
    for (const auto& sc : q.shown) {
      const sdk::Candidate& c = q.parse.candidates[sc.index];
      heard_.candidates.push_back({sdk::render(c.program), !c.core_only});
    }
  });
  session.on<naturalization::RulesDefined>(
      [this](const naturalization::RulesDefined& e) { heard_.rules = e.outcome.rules; });
}

RecordOutcome Recorder::record(const SessionEntry& entry, const std::string& request,
                               const std::string& answer, double ms, const char* origin) {
  std::lock_guard lock(mutex_);
  RecordOutcome outcome;
  ParticipantState& p = state(entry);
  const std::int64_t n = ++exchange_;
  const Json req = Json::parse(request, nullptr, false);  // what the page asked
  auto* tap = entry.session->extension<RecorderTap>();
  std::string qid;
  if (req.is_object() && tap != nullptr) {
    qid = command(entry, p, req, tap->heard(), ms, n, outcome);
    tap->clear();
  }
  append_exchange(
      n, entry.group, entry.participant,
      session_numbers_.count(entry.token) ? Line(session_numbers_[entry.token]) : Line(),
      entry.session->user(), qid, origin, request, answer);
  participants_.save();
  return outcome;
}

void Recorder::record_moderation(const std::string& group, const std::string& account,
                                 const std::string& request, const std::string& answer) {
  std::lock_guard lock(mutex_);
  append_exchange(++exchange_, group, Line(), Line(), account, "", "researcher", request, answer);
}

void Recorder::append_exchange(std::int64_t n, const std::string& group, const Line& participant,
                               const Line& session, const std::string& user, const std::string& qid,
                               const char* origin, const std::string& request,
                               const std::string& answer) {
  // Ordered: the short members first, the request and answer texts last (docs/studio.md §7).
  append_line(exchanges_, Line{{"n", n},
                               {"time", now_iso()},
                               {"group", group},
                               {"participant", participant},
                               {"session", session},
                               {"user", user},
                               {"qid", qid.empty() ? Line() : Line(qid)},
                               {"origin", origin},
                               {"request", request},
                               {"answer", answer},
                               {"sha256", record::sha256_text(corpus::answer_for_digest(answer))}});
}

std::string Recorder::command(const SessionEntry& entry, ParticipantState& p, const Json& req,
                              const RecorderTap::Heard& heard, double ms, std::int64_t exchange,
                              RecordOutcome& outcome) {
  const std::string op = member_text(req, "op");
  const Json studio = req.value("studio", Json::object());
  const std::string why = studio.is_object() ? member_text(studio, "why") : std::string();
  const bool ok = heard.answered && heard.code.empty();
  const std::string status = ok ? std::string("ok") : heard.code.empty() ? "error" : heard.code;
  Live& live = live_[entry.participant];
  const std::string before = p.world_id;
  if (ok && (op == "world" || op == "accept")) p.world_id = world_id(entry);
  Line c;
  if (op == "query" && ok) {
    c = line(entry, p, why == "live" || why == "rerun" ? why : "q", exchange);
    c["utterance"] = member_text(req, "text");
    c["status"] = corpus_status(heard.status);
    const kernel::LastQuery* q = entry.session->last_query();
    c["n_parses"] = q ? q->parse.candidates.size() : 0;
    c["walltime_s"] = ms / 1000.0;
    c["server_ms"] = ms;
    Json candidates = Json::array(), formulas = Json::array();
    for (const auto& k : heard.candidates) {
      candidates.push_back(
          {{"pretty", k.formula}, {"formula", k.formula}, {"core_only", !k.induced}});
      formulas.push_back(k.formula);
    }
    append_line(answers_, Json{{"qid", c["qid"]}, {"candidates", std::move(candidates)}});
    live.last_qid = c["qid"];
    live.last_text = c["utterance"];
    live.last_formulas = std::move(formulas);
  } else if (op == "accept" && ok) {
    c = line(entry, p, "accept", exchange);
    const int rank = req.value("rank", 0);
    c["for_qid"] = live.last_qid;
    c["utterance"] = live.last_text;
    c["rank"] = rank;
    c["world_id"] = before;
    c["next_world_id"] = p.world_id;
    std::string formula;
    if (rank >= 0 && rank < static_cast<int>(live.last_formulas.size()))
      formula = live.last_formulas[static_cast<std::size_t>(rank)];
    c["formula"] = formula;
    p.history.push_back({{"qid", c["qid"]},
                         {"utterance", live.last_text},
                         {"formula", formula},
                         {"world_id", p.world_id},
                         {"before_world_id", before}});
    append_line(queries_, c);
    if (!p.goal_reached && goal_reached(entry, p.task)) {
      p.goal_reached = outcome.goal_reached = true;
      Line g = line(entry, p, "goal", exchange);
      g["for_qid"] = c["qid"];
      if (live.task_started) g["task_ms"] = since_ms(*live.task_started);
      append_line(queries_, g);
    }
    return c["qid"];
  } else if (op == "define") {
    c = line(entry, p, "def", exchange);
    define(entry, p, req, heard, c);
  } else if (op == "delete_rule") {
    c = line(entry, p, "delete", exchange);
    const std::string rule = member_text(req, "rule");
    c["rule"] = rule;
    auto it = rule_defs_.find(rule);
    c["def_id"] = it == rule_defs_.end() ? Json() : Json(it->second.first);
    c["rule_pos"] = it == rule_defs_.end() ? -1 : it->second.second;
    c["rule_index"] = -1;  // the 2018 grammar-log index: none here (docs/studio.md §7)
    c["status"] = status;
  } else if (op == "world" && ok) {
    if (why == "resume") return {};  // the `resume` line says it
    const std::string kind =
        why == "undo" || why == "reset" || why == "task_start" ? why : std::string("world");
    if (kind == "task_start") {
      const int task = studio.value("task", p.task + 1);
      const auto& tasks = study_->tasks();
      const bool had_goal = p.task >= 0 && p.task < static_cast<int>(tasks.size()) &&
                            !tasks[static_cast<std::size_t>(p.task)].goal.empty();
      if (had_goal && !p.goal_reached && task != p.task) {
        Line skip = line(entry, p, "task_skip", exchange);
        if (live.task_started) skip["task_ms"] = since_ms(*live.task_started);
        append_line(queries_, skip);
      }
      p.task = task;
      p.goal_reached = false;
      live.task_started = std::chrono::steady_clock::now();
      p.history = Json::array();
    } else if (kind == "undo" && !p.history.empty()) {
      p.history.erase(p.history.size() - 1);
    } else if (kind == "reset") {
      p.history = Json::array();
    }
    c = line(entry, p, kind, exchange);
    c["world_id"] = before;
    c["next_world_id"] = p.world_id;
  } else {
    return {};  // rules, state, refusals: exchanges.jsonl only
  }
  append_line(queries_, c);
  return c["qid"];
}

void Recorder::define(const SessionEntry& entry, ParticipantState& p, const Json& req,
                      const RecorderTap::Heard& heard, Line& c) {
  const bool ok = heard.answered && heard.code.empty();
  const Json ranks = req.value("ranks", Json::array());
  const Json studio = req.value("studio", Json::object());
  const bool from_history = studio.is_object() && member_text(studio, "why") == "history";
  Json steps = studio.is_object() ? studio.value("steps", Json::array()) : Json::array();
  int first = -1, last = -1;
  if (from_history && steps.is_array() && steps.size() == 2 && steps[0].is_number_integer() &&
      steps[1].is_number_integer()) {
    first = steps[0].get<int>();
    last = steps[1].get<int>();
  }
  const int n_history = static_cast<int>(p.history.size());
  const bool range_ok = first >= 0 && first <= last && last < n_history;
  Json body = Json::array(), history_qids = Json::array();
  std::size_t i = 0;
  for (const auto& b : req.value("body", Json::array())) {
    Json lineout;
    if (b.is_string()) {
      const int rank = i < ranks.size() && ranks[i].is_number_integer() ? ranks[i].get<int>() : 0;
      lineout = {{"utterance", b}, {"formula", ""}, {"rank", rank}};
    } else if (b.is_object()) {
      lineout = {{"utterance", member_text(b, "text")}, {"formula", member_text(b, "formula")}};
    }
    if (range_ok && first + static_cast<int>(i) <= last) {
      const Json& step = p.history[static_cast<std::size_t>(first) + i];
      lineout["accept_qid"] = step.value("qid", Json());
      history_qids.push_back(step.value("qid", Json()));
    }
    body.push_back(std::move(lineout));
    ++i;
  }
  c["head"] = member_text(req, "head");
  c["body"] = body;
  c["def_id"] = "d:" + c["qid"].get<std::string>();
  c["status"] = ok ? std::string("ok") : heard.code.empty() ? "error" : heard.code;
  c["from_history"] = from_history ? history_qids : Json();
  Json induced = Json::array();
  int pos = 0;
  for (const auto& r : ok ? heard.rules : std::vector<sdk::RulePtr>()) {
    rule_defs_[r->id] = {c["def_id"], pos++};
    Json rhs = Json::array();
    for (const auto& symbol : r->rhs) rhs.push_back(symbol.text);
    const std::string how = sdk::to_string(r->how);
    induced.push_back({{"id", r->id},
                       {"line", ++rule_lines_[c["source"].get<std::string>()]},
                       {"lhs", r->lhs},
                       {"rhs", std::move(rhs)},
                       {"semantics", sdk::render(r->sem)},
                       {"how", how},
                       {"simple_packing", how == "simple"},
                       {"align", how == "alignment"}});
  }
  append_line(definitions_, Json{{"def_id", c["def_id"]},
                                 {"origin", "query_log"},
                                 {"source", c["source"]},
                                 {"group", entry.group},
                                 {"session", entry.participant},
                                 {"user", c["user"]},
                                 {"kind", "def"},
                                 {"head", c["head"]},
                                 {"body", body},
                                 {"line", c["line"]},
                                 {"rules_status", ok ? "induced" : "failed"},
                                 {"induced_rules", std::move(induced)}});
  // A phrase taught from history: its steps collapse into one (docs/studio.md §7).
  if (ok && range_ok) {
    std::string formula = "{";
    Json replaced = Json::array();
    for (int k = first; k <= last; ++k) {
      const Json& step = p.history[static_cast<std::size_t>(k)];
      formula += (k > first ? ";" : "") + member_text(step, "formula");
      replaced.push_back(step);
    }
    Json collapsed{
        {"qid", c["qid"]},
        {"utterance", c["head"]},
        {"formula", formula + "}"},
        {"world_id", p.history[static_cast<std::size_t>(last)]["world_id"]},
        {"before_world_id", p.history[static_cast<std::size_t>(first)]["before_world_id"]},
        {"steps", std::move(replaced)}};
    Json kept = Json::array();
    for (int k = 0; k < first; ++k) kept.push_back(p.history[static_cast<std::size_t>(k)]);
    kept.push_back(std::move(collapsed));
    for (int k = last + 1; k < n_history; ++k)
      kept.push_back(p.history[static_cast<std::size_t>(k)]);
    p.history = std::move(kept);
  }
}

void Recorder::event(const SessionEntry& entry, const Json& body) {
  std::lock_guard lock(mutex_);
  ParticipantState& p = state(entry);
  const std::string kind = member_text(body, "kind");
  const Live& live = live_[entry.participant];
  Line c = line(entry, p, kind, std::nullopt);
  if (kind == "flip") {
    c["for_qid"] = live.last_qid;
    c["utterance"] = live.last_text;
    c["rank"] = body.value("rank", 0);
    c["formula"] = member_text(body, "formula");
  } else if (kind == "reject") {
    c["for_qid"] = live.last_qid;
    c["utterance"] = live.last_text;
    c["formulas"] = live.last_formulas;
  } else if (kind == "page_load") {
    c["reloaded"] = body.value("reloaded", false);
  }
  append_line(queries_, c);
  participants_.save();
}

Json Recorder::page_state(const std::string& participant) {
  std::lock_guard lock(mutex_);
  const ParticipantState* p = participants_.find(participant);
  if (p == nullptr) return nullptr;
  Json history = Json::array();
  for (const auto& step : p->history) {
    auto w = worlds_by_id_.find(member_text(step, "world_id"));
    history.push_back({{"qid", step.value("qid", Json())},
                       {"utterance", step.value("utterance", Json())},
                       {"formula", step.value("formula", Json())},
                       {"world", w == worlds_by_id_.end() ? Json() : w->second}});
  }
  return {{"participant", p->participant},
          {"teaching", p->group != "A"},
          {"task", p->task},
          {"goal_reached", p->goal_reached},
          {"history", std::move(history)}};
}

void Recorder::audit(const std::string& account, const std::string& peer, const std::string& action,
                     const Json& details) {
  nlohmann::ordered_json line{
      {"time", now_iso()}, {"account", account}, {"peer", peer}, {"action", action}};
  for (const auto& [key, value] : details.items()) line[key] = value;
  std::lock_guard lock(mutex_);
  append_line(audit_, line);
  audit_.sync();
}

Json Recorder::overview() {
  std::lock_guard lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  const auto& tasks = study_->tasks();
  Json list = Json::array();
  for (const auto& p : participants_.all()) {
    const bool in_task = p.task >= 0 && p.task < static_cast<int>(tasks.size());
    Json counts = Json::object();
    for (const auto& k : kCounted) {
      auto it = p.counts.find(k);
      counts[k] = it == p.counts.end() ? 0 : it->second;
    }
    list.push_back(
        {{"participant", p.participant},
         {"account", p.account},
         {"group", p.group},
         {"task", p.task},
         {"task_name", in_task ? Json(tasks[static_cast<std::size_t>(p.task)].name) : Json()},
         {"goal_reached", p.goal_reached},
         {"online", p.last_request.time_since_epoch().count() != 0 &&
                        now - p.last_request < std::chrono::seconds(120)},
         {"last_seen", p.last_seen},
         {"counts", std::move(counts)}});
  }
  Json names = Json::array();
  for (const auto& t : tasks) names.push_back(t.name);
  Json files = Json::array();
  for (const auto& f : Recorder::files()) {
    std::error_code ec;
    const auto size = fs::file_size(fs::path(dir_) / f, ec);
    if (!ec) files.push_back({{"name", f}, {"bytes", size}});
  }
  return {{"ok", true},
          {"study",
           {{"name", study_->name()},
            {"open", participants_.open()},
            {"groups", study_->groups()},
            {"tasks", std::move(names)}}},
          {"participants", std::move(list)},
          {"files", std::move(files)}};
}

}  // namespace flipper::studio

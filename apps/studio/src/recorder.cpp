#include "recorder.hpp"

#include <chrono>
#include <ctime>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "flipper/sdk/errors.hpp"
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

std::ofstream open_append(const fs::path& path) {
  std::ofstream out(path, std::ios::app);
  if (!out) throw sdk::Error(sdk::codes::kBadConfig, "study: cannot write '" + path.string() + "'");
  return out;
}

}  // namespace

Recorder::Recorder(std::shared_ptr<const Study> study) : study_(std::move(study)) {
  const fs::path dir = study_->record_dir();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw sdk::Error(sdk::codes::kBadConfig,
                     "study: cannot create '" + dir.string() + "': " + ec.message());
  queries_ = open_append(dir / "queries.jsonl");
  worlds_ = open_append(dir / "worlds.jsonl");
  definitions_ = open_append(dir / "definitions.jsonl");
  answers_ = open_append(dir / "original-answers.jsonl");
}

void Recorder::write(std::ofstream& out, const Json& line) {
  out << line.dump(-1, ' ', false, Json::error_handler_t::replace) << '\n';
  out.flush();
}

void Recorder::write_sessions() {
  const fs::path path = fs::path(study_->record_dir()) / "sessions.json";
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << sessions_.dump(1) << '\n';
  }
  fs::rename(tmp, path);
}

std::string Recorder::world_id(const SessionEntry& entry) {
  const Json world = entry.session->world_json(entry.session->world());
  const std::string text = world.dump();
  std::ostringstream id;
  id << 'w' << std::hex << std::hash<std::string>{}(text);
  if (worlds_written_.insert(id.str()).second) {
    Json line{{"world_id", id.str()}};
    for (const auto& [k, v] : world.items()) line[k] = v;
    write(worlds_, line);
  }
  return id.str();
}

void Recorder::session_started(const SessionEntry& entry) {
  Participant& p = participants_[entry.token];
  p.world_id = world_id(entry);
  preloaded(entry.group);
  sessions_.push_back({{"source", study_->source(entry.group)}, {"session", entry.participant}});
  write_sessions();
}

void Recorder::preloaded(const std::string& group) {
  if (group != "C" || study_->preload().empty() || !preloaded_.insert(group).second) return;
  std::ifstream in(study_->preload());
  std::string text;
  int n = 0;
  while (std::getline(in, text)) {
    const Json d = Json::parse(text, nullptr, false);
    if (!d.is_object()) continue;
    Json body = Json::array();
    for (const auto& b : d.value("body", Json::array())) body.push_back({{"utterance", b}});
    write(definitions_, {{"def_id", "p:" + study_->source(group) + "#" + std::to_string(++n)},
                         {"origin", "preloaded"},
                         {"source", study_->source(group)},
                         {"group", group},
                         {"kind", "def"},
                         {"user", d.value("author", std::string("expert"))},
                         {"head", d.value("head", std::string())},
                         {"body", std::move(body)},
                         {"line", n}});
  }
}

Json Recorder::command(const SessionEntry& entry, Participant& p, const std::string& kind) {
  ++line_;
  ++p.seq;
  const std::string source = study_->source(entry.group);
  return Json{{"qid", source + "#" + std::to_string(line_)},
              {"source", source},
              {"file", "studio"},
              {"line", line_},
              {"cohort", study_->name()},
              {"group", entry.group},
              {"session", entry.participant},
              {"uid", entry.participant},
              {"participant", entry.participant},
              {"in_authors_tables", true},
              {"user", entry.session->user()},
              {"syntax", "studio"},
              {"seq", p.seq},
              {"time", now_iso()},
              {"phase", "task"},
              {"kind", kind},
              {"split", "studio"}};
}

void Recorder::record(const SessionEntry& entry, const Json& request, const std::string& answer,
                      double ms) {
  Participant& p = participants_[entry.token];
  const std::string op =
      request.value("op", Json()).is_string() ? request["op"].get<std::string>() : std::string();
  const Json a = Json::parse(answer, nullptr, false);
  const bool ok = a.is_object() && a.value("ok", false);
  const std::string before = p.world_id;
  if (op == "world" || op == "accept") p.world_id = world_id(entry);
  if (op == "query" && ok) {
    Json c = command(entry, p, "q");
    c["utterance"] = request.value("text", std::string());
    c["world_id"] = before;
    c["next_world_id"] = before;
    c["status"] = corpus_status(a.value("status", std::string()));
    const kernel::LastQuery* q = entry.session->last_query();
    c["n_parses"] = q ? q->parse.candidates.size() : 0;
    c["walltime_s"] = ms / 1000.0;
    c["server_ms"] = ms;
    Json candidates = Json::array();
    for (const auto& k : a["candidates"])
      candidates.push_back({{"pretty", k.value("formula", std::string())},
                            {"formula", k.value("formula", std::string())},
                            {"core_only", !k.value("induced", false)}});
    write(answers_, {{"qid", c["qid"]}, {"candidates", candidates}});
    p.last_qid = c["qid"];
    p.last_text = c["utterance"];
    p.last_candidates = std::move(candidates);
    write(queries_, c);
  } else if (op == "accept" && ok) {
    Json c = command(entry, p, "accept");
    const auto rank = request.value("rank", -1);
    c["for_qid"] = p.last_qid;
    c["utterance"] = p.last_text;
    c["world_id"] = before;
    c["next_world_id"] = p.world_id;
    if (rank >= 0 && rank < static_cast<int>(p.last_candidates.size()))
      c["formula"] = p.last_candidates[static_cast<std::size_t>(rank)]["formula"];
    write(queries_, c);
  } else if (op == "define") {
    Json c = command(entry, p, "def");
    Json body = Json::array();
    for (const auto& b : request.value("body", Json::array()))
      if (b.is_string()) body.push_back({{"utterance", b}, {"formula", ""}});
    c["head"] = request.value("head", std::string());
    c["body"] = body;
    c["def_id"] = "d:" + c["qid"].get<std::string>();
    c["world_id"] = before;
    c["next_world_id"] = before;
    c["status"] = ok ? "ok" : a["error"].value("code", std::string("error"));
    Json def{{"def_id", c["def_id"]},
             {"origin", "query_log"},
             {"source", c["source"]},
             {"group", entry.group},
             {"session", entry.participant},
             {"user", c["user"]},
             {"kind", "def"},
             {"head", c["head"]},
             {"body", body},
             {"line", c["line"]},
             {"rules_status", ok ? "induced" : "failed"}};
    write(definitions_, def);
    write(queries_, c);
  } else if (op == "delete_rule") {
    Json c = command(entry, p, "delete");
    c["rule"] = request.value("rule", std::string());
    c["rule_index"] = -1;  // ids are this system's own; the replay's deletion map cannot use them
    c["world_id"] = before;
    c["next_world_id"] = before;
    write(queries_, c);
  }
}

}  // namespace flipper::studio

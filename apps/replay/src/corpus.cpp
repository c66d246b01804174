// Loading the corpus split (JSON Lines) into plain structs.
#include "flipper/replay/corpus.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"

namespace flipper::replay {
namespace {

using nlohmann::json;

std::string str(const json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}
std::optional<std::string> opt_str(const json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || !it->is_string()) return std::nullopt;
  return it->get<std::string>();
}
int integer(const json& j, const char* key, int fallback = 0) {
  auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<int>() : fallback;
}

std::vector<BodyLine> body_of(const json& j) {
  std::vector<BodyLine> out;
  if (auto it = j.find("body"); it != j.end() && it->is_array())
    for (const auto& b : *it)
      out.push_back(
          {str(b, "utterance"), str(b, "formula"), integer(b, "rank", -1), str(b, "accept_qid")});
  return out;
}

// Calls f(json) for each non-empty line; a bad line is a bad_corpus error naming file and line.
template <class F>
void for_each_line(const std::string& path, bool required, F&& f) {
  std::ifstream in(path);
  if (!in) {
    if (!required) return;
    throw sdk::Error(kBadCorpus, "cannot read corpus file '" + path + "'");
  }
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      f(json::parse(line));
    } catch (const json::exception& e) {
      throw sdk::Error(kBadCorpus, path + ":" + std::to_string(n) + ": " + e.what());
    }
  }
}

Command command_of(const json& j) {
  Command c;
  c.qid = str(j, "qid");
  c.source = str(j, "source");
  c.group = str(j, "group");
  c.session = str(j, "session");
  c.user = str(j, "user");
  if (c.user.empty()) c.user = c.session;
  c.kind = str(j, "kind");
  c.phase = str(j, "phase");
  c.syntax = str(j, "syntax");
  c.participant = opt_str(j, "participant");
  c.in_authors_tables = j.value("in_authors_tables", false) == true;
  c.line = integer(j, "line");
  c.utterance = str(j, "utterance");
  c.world_id = str(j, "world_id");
  c.next_world_id = str(j, "next_world_id");
  c.status = str(j, "status");
  c.n_parses = integer(j, "n_parses");
  if (auto it = j.find("walltime_s"); it != j.end() && it->is_number())
    c.walltime_s = it->get<double>();
  c.author = opt_str(j, "author");
  c.formula = str(j, "formula");
  c.for_qid = str(j, "for_qid");
  c.head = str(j, "head");
  c.def_id = str(j, "def_id");
  c.body = body_of(j);
  c.rule_index = integer(j, "rule_index", -1);
  c.rule = str(j, "rule");
  c.rule_pos = integer(j, "rule_pos", -1);
  if (c.qid.empty() || c.source.empty() || c.kind.empty())
    throw sdk::Error(kBadCorpus, "a command needs qid, source and kind");
  return c;
}

Definition definition_of(const json& j) {
  Definition d;
  d.def_id = str(j, "def_id");
  d.origin = str(j, "origin");
  d.source = str(j, "source");
  d.group = str(j, "group");
  d.session = str(j, "session");
  d.kind = str(j, "kind");
  d.head = str(j, "head");
  d.rules_status = str(j, "rules_status");
  d.user = opt_str(j, "user");
  d.line = integer(j, "line");
  d.body = body_of(j);
  if (auto it = j.find("induced_rules"); it != j.end() && it->is_array())
    for (const auto& r : *it) {
      LoggedRule rule{integer(r, "line"),
                      r.value("simple_packing", false),
                      r.value("align", false),
                      str(r, "lhs"),
                      {},
                      str(r, "semantics")};
      if (auto rhs = r.find("rhs"); rhs != r.end() && rhs->is_array())
        for (const auto& s : *rhs)
          if (s.is_string()) rule.rhs.push_back(s.get<std::string>());
      d.rules.push_back(std::move(rule));
    }
  return d;
}

}  // namespace

json protocol_world(const json& r) {
  json w = json::object();
  for (const char* key : {"walls", "items", "robot", "rooms", "bounds"})
    if (auto it = r.find(key); it != r.end()) w[key] = *it;
  return w;
}

const Run* Corpus::find_run(const std::string& source) const {
  for (const auto& r : runs)
    if (r.source == source) return &r;
  return nullptr;
}

std::vector<const Definition*> Corpus::preloaded(const std::string& source) const {
  std::vector<const Definition*> out;
  for (const auto& d : definitions)
    if (d.source == source && (d.origin == "preloaded" || d.origin == "grammar_log_only"))
      out.push_back(&d);
  // The grammar log order: preloaded files come before the run's own rules.
  std::stable_sort(out.begin(), out.end(), [](const Definition* a, const Definition* b) {
    int ka = a->rules.empty() ? a->line : a->rules.front().line;
    int kb = b->rules.empty() ? b->line : b->rules.front().line;
    return ka < kb;
  });
  return out;
}

Corpus load_corpus(const std::string& dir) {
  Corpus c;
  c.dir = dir;
  for_each_line(dir + "/worlds.jsonl", true, [&](const json& j) {
    std::string id = str(j, "world_id");
    if (id.empty()) throw sdk::Error(kBadCorpus, "a world needs a world_id");
    c.worlds.emplace(std::move(id), protocol_world(j));
  });
  for_each_line(dir + "/queries.jsonl", true,
                [&](const json& j) { c.commands.push_back(command_of(j)); });
  for_each_line(dir + "/definitions.jsonl", false, [&](const json& j) {
    c.definition_index.emplace(str(j, "def_id"), c.definitions.size());
    c.definitions.push_back(definition_of(j));
  });
  for_each_line(dir + "/original-answers.jsonl", false, [&](const json& j) {
    OriginalAnswer a;
    if (auto it = j.find("candidates"); it != j.end() && it->is_array())
      for (const auto& k : *it) {
        OriginalAnswer::Candidate cand{str(k, "pretty"), str(k, "formula"),
                                       k.value("core_only", false), json()};
        if (auto r = k.find("result"); r != k.end() && r->is_object() && r->contains("path"))
          cand.path = (*r)["path"];
        a.candidates.push_back(std::move(cand));
      }
    if (auto it = j.find("accepted_rank"); it != j.end() && it->is_number())
      a.accepted_rank = it->get<int>();
    c.answers.emplace(str(j, "qid"), std::move(a));
  });

  // Runs in order of first appearance; commands stay in file order (the README's log order).
  std::map<std::string, std::map<std::string, int>> group_votes;
  for (std::size_t i = 0; i < c.commands.size(); ++i) {
    const Command& cmd = c.commands[i];
    auto it = std::find_if(c.runs.begin(), c.runs.end(),
                           [&](const Run& r) { return r.source == cmd.source; });
    if (it == c.runs.end()) it = c.runs.insert(c.runs.end(), Run{cmd.source, "", {}});
    it->commands.push_back(i);
    ++group_votes[cmd.source][cmd.group];
  }
  for (auto& r : c.runs) {
    int best = -1;
    for (const auto& [g, n] : group_votes[r.source])
      if (n > best) best = n, r.group = g;
  }
  return c;
}

}  // namespace flipper::replay

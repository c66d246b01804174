#pragma once
// The dev corpus (FLIPPER_STUDY_DIR/dev, i.e. data/study2018/dev) as protocol request lines,
// session by session (as bench/scale replays it): user, then world + query per logged query, accept
// rank 0, define, and a state at the end of each. Shared by the protocol-2 oracle and the
// byte-identity golden test. `shown` > 0 asks every query for that many candidates ("k").
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flipper::testsupport {

inline const std::string kDev = std::string(FLIPPER_STUDY_DIR) + "/dev/";

inline std::vector<nlohmann::json> read_jsonl(const std::string& path) {
  std::vector<nlohmann::json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  return out;
}

inline std::vector<std::string> dev_stream(int shown = 0) {
  std::map<std::string, nlohmann::json> worlds, defs;
  for (auto& w : read_jsonl(kDev + "worlds.jsonl")) {
    nlohmann::json obj;
    for (const char* k : {"walls", "items", "robot", "rooms", "bounds"})
      if (w.contains(k)) obj[k] = w[k];
    worlds[w["world_id"].get<std::string>()] = obj;
  }
  for (auto& d : read_jsonl(kDev + "definitions.jsonl")) defs[d["def_id"].get<std::string>()] = d;
  std::vector<std::string> order;
  std::map<std::string, std::vector<nlohmann::json>> by_session;
  for (auto& q : read_jsonl(kDev + "queries.jsonl")) {
    const std::string s = q.value("session", "");
    if (!by_session.count(s)) order.push_back(s);
    by_session[s].push_back(q);
  }
  std::vector<std::string> out;
  for (const auto& s : order) {
    out.push_back(
        nlohmann::json{{"op", "user"}, {"name", by_session[s].front().value("user", s)}}.dump());
    for (const auto& q : by_session[s]) {
      const std::string kind = q.value("kind", "");
      if (kind == "q" && q["utterance"].is_string()) {
        if (auto w = worlds.find(q.value("world_id", "")); w != worlds.end())
          out.push_back(nlohmann::json{{"op", "world"}, {"world", w->second}}.dump());
        nlohmann::json query{{"op", "query"}, {"text", q["utterance"]}};
        if (shown > 0) query["k"] = shown;
        out.push_back(query.dump());
      } else if (kind == "accept") {
        out.push_back(R"({"op":"accept","rank":0})");
      } else if (kind == "def" || kind == "def_ret" || kind == "def_iso") {
        auto d = defs.find("d:" + q.value("qid", ""));
        if (d == defs.end()) continue;
        nlohmann::json body = nlohmann::json::array();
        for (const auto& b : d->second["body"]) body.push_back(b["utterance"]);
        out.push_back(
            nlohmann::json{{"op", "define"}, {"head", d->second["head"]}, {"body", body}}.dump());
      }
    }
    out.push_back(R"({"op":"state"})");
  }
  return out;
}

}  // namespace flipper::testsupport

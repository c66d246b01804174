#pragma once
// Reading the shared corpus and probe files for the differential tests.
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flipper::testsupport {

inline std::vector<nlohmann::json> read_jsonl(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<nlohmann::json> out;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  return out;
}

inline std::string study_path(const std::string& rel) {
  return std::string(FLIPPER_STUDY_DIR) + "/" + rel;
}

/// worlds.jsonl by world_id.
inline std::map<std::string, nlohmann::json> corpus_worlds() {
  std::map<std::string, nlohmann::json> out;
  for (auto& w : read_jsonl(study_path("dev/worlds.jsonl"))) {
    std::string id = w["world_id"];
    out.emplace(std::move(id), std::move(w));
  }
  return out;
}

}  // namespace flipper::testsupport

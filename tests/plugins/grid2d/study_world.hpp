#pragma once
// The map of the 2018 user studies (core-language §10), read from the corpus as it is: the
// corpus world object carries extra bookkeeping fields, which world plugins ignore.
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace flipper::testsupport {

/// Every line of the corpus world file (one world object per line).
inline std::vector<std::string> corpus_worlds() {
  std::ifstream in(std::string(FLIPPER_STUDY_DIR) + "/dev/worlds.jsonl");
  if (!in) throw std::runtime_error("cannot read corpus/dev/worlds.jsonl");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  return lines;
}

/// The study map: corpus world wdd05b0e5ff41.
inline std::string study_world_json() {
  for (const auto& line : corpus_worlds())
    if (line.find("\"wdd05b0e5ff41\"") != std::string::npos) return line;
  throw std::runtime_error("corpus world wdd05b0e5ff41 not found");
}

}  // namespace flipper::testsupport

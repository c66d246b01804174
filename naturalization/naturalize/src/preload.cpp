// Preloading a definitions file (docs/naturalization.md §5): replayed through induction so rules
// are always induced by this system, never copied. A definition that does not load is reported:
// a warning naming it and why, and a row in the store that `flipper lexicon list` and `export`
// show.
#include <ctime>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "flipper/kernel/limits.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/config/regular_file.hpp"

namespace flipper::naturalization {

void Naturalizer::preload(const std::string& path) {
  std::istringstream in(toolkit::config::read_regular_file(
      path, kernel::InputLimits::from_config(runtime_->config).max_file_bytes,
      "lexicon.preload file", sdk::codes::kBadConfig));
  // A restart must not replay what the store already holds.
  std::set<std::tuple<std::string, std::vector<std::string>, std::string>> stored;
  for (const auto& d : store_->definitions()) stored.emplace(d.head, d.body, d.author);

  const auto now = static_cast<std::int64_t>(std::time(nullptr));
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    DefineRequest req;
    req.via = "preload";
    try {
      const auto j = nlohmann::json::parse(line);
      req.head = j.at("head").get<std::string>();
      req.body = j.at("body").get<std::vector<std::string>>();
      req.user = j.value("author", std::string("preload"));
    } catch (const std::exception& e) {
      throw sdk::Error(sdk::codes::kBadConfig,
                       "lexicon.preload '" + path + "' line " + std::to_string(line_no) +
                           ": expected {\"head\",\"body\":[...],\"author\"}: " + e.what());
    }
    if (stored.count({req.head, req.body, req.user})) {
      ++preload_report_.already_stored;
      continue;
    }
    try {
      define(req);
      ++preload_report_.replayed;
    } catch (const sdk::Error& e) {
      // A store fault stops the start, unless the store opened degraded: then every definition
      // is refused alike and reported like any other.
      if (lexicon_codes::is_store_fault(e.code()) && !store_->write_refusal()) throw;
      PreloadFailure f{
          path, static_cast<std::int64_t>(line_no), req.head, req.user, e.code(), e.what(), now};
      options_.warn("lexicon.preload '" + path + "' line " + std::to_string(line_no) +
                    ": definition '" + f.head + "' (author '" + f.author +
                    "') was not loaded: " + f.code + ": " + f.message);
      preload_report_.failures.push_back(std::move(f));
    }
  }
  // Shown by `flipper lexicon list` and `export` until a later start loads them (best effort: a
  // store that cannot be written keeps only the warnings above).
  store_->record_preload_failures(path, preload_report_.failures);
}

}  // namespace flipper::naturalization

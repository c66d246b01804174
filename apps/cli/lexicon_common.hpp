#pragma once
// What the `flipper lexicon` subcommands share (lexicon.cpp, lexicon_history.cpp,
// lexicon_moderation.cpp).
#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>

#include "common.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::cli {

/// The store of the config's lexicon.path (an existing one: bad_config when there is none).
std::unique_ptr<naturalization::LexiconStore> open_lexicon_store(const CommonOptions& common);
/// `--user U`, else $USER, else "unknown": who a history entry names.
std::string lexicon_user(const std::string& user);

/// A subcommand's callback: runs `action(args)`, an sdk::Error reported as `lexicon WHAT` with
/// its code's exit status (common.hpp status_for).
template <class Args>
std::function<int()> guarded(const char* what, int (*action)(const Args&), const Args& args) {
  return [what, action, &args] {
    try {
      return action(args);
    } catch (const sdk::Error& e) {
      return report_error(std::string("lexicon ") + what, e.code(), e.what(), status_for(e.code()));
    }
  };
}

/// lexicon log|diff|tag|revert (lexicon_history.cpp).
void add_lexicon_history_commands(CLI::App& lexicon);
/// lexicon pending|approve|reject (lexicon_moderation.cpp).
void add_lexicon_moderation_commands(CLI::App& lexicon);

}  // namespace flipper::cli

#pragma once
// What the `flipper lexicon` subcommands share (lexicon.cpp, lexicon_history.cpp,
// lexicon_moderation.cpp).
#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "common.hpp"
#include "flipper/naturalization/lexicon_store.hpp"

namespace flipper::cli {

/// The store of the config's lexicon.path (an existing one: bad_config when there is none).
std::unique_ptr<naturalization::LexiconStore> open_lexicon_store(const CommonOptions& common);
/// `--user U`, else $USER, else "unknown": who a history entry names.
std::string lexicon_user(const std::string& user);

/// lexicon log|diff|tag|revert (lexicon_history.cpp).
void add_lexicon_history_commands(CLI::App& lexicon);
/// lexicon pending|approve|reject (lexicon_moderation.cpp).
void add_lexicon_moderation_commands(CLI::App& lexicon);

}  // namespace flipper::cli

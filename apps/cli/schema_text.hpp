#pragma once
// A parameter schema as text: the table of `flipper plugins NAME` (a plugin's params) and of
// `flipper config explain` (the kernel's keys), and the Markdown table of docs/config.md. One
// rendering, so a plugin's params and the kernel's keys read alike.
#include <string>
#include <vector>

#include "flipper/sdk/params.hpp"

namespace flipper::cli {

/// "[1, 100]", ">= 0", "<= 5", "one of: a, b", or "-". Integer bounds print as integers.
std::string allowed_text(const sdk::ParamSpec& p);
/// The default as a config writes it, "(required)", "(none)", or for a key of an optional
/// section of `schema` "(none; needed with SECTION)".
std::string default_text(const sdk::ParamSpec& p, const sdk::ParamSchema* schema = nullptr);
/// The width tables wrap to: the terminal's, else $COLUMNS, else 100.
std::size_t terminal_width();
/// `text`'s words in lines of at most `width` characters (a longer word is cut, after a '/' where
/// it can be).
std::vector<std::string> wrap_words(const std::string& text, std::size_t width);
/// The specs whose name is `prefix` or lies below it (all for "").
std::vector<const sdk::ParamSpec*> specs_under(const sdk::ParamSchema& schema,
                                               const std::string& prefix);
struct TableOptions {
  const sdk::ParamSchema* schema = nullptr;  ///< the specs' schema (for optional sections)
  std::string name_prefix;                   ///< put before each name ("planner.params.")
  std::size_t width = 100;                   ///< the description column wraps to fit this
};
/// Aligned columns NAME TYPE DEFAULT ALLOWED DESCRIPTION, each line starting with `indent`; a
/// long description wraps onto lines of its own column.
std::string text_table(const std::vector<const sdk::ParamSpec*>& specs, const std::string& header,
                       const std::string& indent, const TableOptions& options = {});
/// One Markdown table row per key, with a row per declared section before its keys.
std::string markdown_table(const sdk::ParamSchema& schema);

}  // namespace flipper::cli

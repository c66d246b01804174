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
/// The default as a config writes it, "(required)" or "(none)".
std::string default_text(const sdk::ParamSpec& p);
/// The specs whose name is `prefix` or lies below it (all for "").
std::vector<const sdk::ParamSpec*> specs_under(const sdk::ParamSchema& schema,
                                               const std::string& prefix);
/// Aligned columns NAME TYPE DEFAULT ALLOWED DESCRIPTION, each line starting with `indent`.
std::string text_table(const std::vector<const sdk::ParamSpec*>& specs, const std::string& header,
                       const std::string& indent);
/// One Markdown table row per key, with a row per declared section before its keys.
std::string markdown_table(const sdk::ParamSchema& schema);

}  // namespace flipper::cli

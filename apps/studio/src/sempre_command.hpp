#pragma once
// The commands of the 2018 server's HTTP API, read from the `q` parameter (docs/sempre.md §
// "Commands"): ten s-expression forms whose string arguments are JSON string literals, except the
// head of a definition, which the client writes between quotes without escaping. Text that does
// not start with "(:" is a query, as the original treated it.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace flipper::studio {

struct SempreCommand {
  enum class Kind { context, query, accept, reject, define, dictionary, delete_rule };
  Kind kind = Kind::query;
  std::string name;  ///< the command as written: "context", "q", "def_ret", ...
  /// context: the world's JSON text; query, accept, reject: the utterance; define: the head.
  std::string text;
  std::string formula;     ///< accept: the accepted candidate's formula
  std::string body;        ///< define: the body's JSON text (a list of [utterance, formula])
  std::int64_t index = 0;  ///< delete: the rule's dictionary index
};

/// Reads one command. Throws sdk::Error(bad_request) saying what is wrong (an unknown command,
/// a missing or malformed argument).
SempreCommand parse_sempre_command(std::string_view q);

/// One [utterance, formula] step of a definition's body.
struct SempreStep {
  std::string utterance;
  std::string formula;
};
/// The body's JSON text as a list of steps. Throws sdk::Error(bad_request).
std::vector<SempreStep> parse_sempre_body(std::string_view json);

}  // namespace flipper::studio

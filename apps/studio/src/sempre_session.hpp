#pragma once
// What each /sempre command does to one session (docs/sempre.md has the mapping table): the
// context becomes the session's world, a query is the typed `query`, an accept the typed `accept`
// of the reading its formula names, a definition naturalization's typed `define` with each body
// line's program, the dictionary its `rules`, a deletion its `delete_rule`. Every call runs under
// the kernel lock (Api::with_kernel).
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "sempre_command.hpp"

namespace flipper::studio {

/// The original's cap on the candidates of one answer (beyond it: "Exceeded max options").
inline constexpr std::int64_t kSempreMaxCandidates = 50;

/// The lexicon author of a sessionId's rules, "sempre:<id>": a name of its own namespace, which
/// no /api/v1 session can take (docs/sempre.md § "Who is who").
std::string sempre_user(const std::string& session_id);
/// A rule author as the dictionary's `uid`: the sessionId for /sempre authors, else the name.
std::string sempre_uid(const std::string& author);

/// One answer: `stats` (the command's own members; the endpoint adds type, count, walltime),
/// `lines` (messages; the client shows a non-empty list as an alert) and `candidates`, each
/// already written as its JSON object (candidate_text): a candidate is written once, where it is
/// made, and the answer is assembled from the texts (docs/sempre.md § "Answers").
struct SempreAnswer {
  nlohmann::json stats = nlohmann::json::object();
  std::vector<std::string> lines;
  std::vector<std::string> candidates;
};

/// A candidate's JSON object, the bytes nlohmann's dump (invalid UTF-8 replaced) writes for
/// {"formula": formula, "prettyString": formula, "score": score, "prob": prob, "value": value,
/// "anchored": true}: members in its (sorted) key order, NaN and infinities as null.
std::string candidate_text(const std::string& formula, double score, double prob,
                           const std::string& value);

struct SempreSession {
  kernel::Session* session = nullptr;  ///< owned by the server's session table (SessionEntry)
  std::string context;                 ///< the context text the session's world was loaded from
  std::string context_error;           ///< why the last context was refused ("" when it loaded)
  /// The memory budget (docs/studio.md §4): reserves the most a world may take before a context
  /// is loaded (false: the budget cannot hold it, the context is refused `server_busy`), and
  /// charges what the session's world takes after. Empty: no budget.
  std::function<bool()> reserve_world;
  std::function<void()> charge_world;
};

/// Runs one command. Refusals (sdk::Error) propagate; the endpoint turns them into `lines`.
SempreAnswer run_sempre_command(SempreSession& s, const SempreCommand& command);

}  // namespace flipper::studio

#pragma once
/// @file query_service.hpp
/// The typed requests and results of the session's query service (docs/architecture.md §4):
/// `Session::query`, `accept`, `open_world` and `select_user` take these and return these.
/// Every front end calls them — `flipper run`, `repl`, `replay` directly, the protocol's JSON ops
/// (docs/protocol.md) as a thin adapter that reads the fields, calls the same function and writes
/// the result — so validation, limits, deadlines and error codes live in one place.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flipper/sdk/derivation.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::kernel {

/// A candidate shown to the user, with what is needed to accept it.
struct ShownCandidate {
  std::size_t index = 0;                    ///< into LastQuery::parse.candidates
  sdk::DerivationPtr derivation;            ///< the derivation whose rules are reported/credited
  std::vector<sdk::RulePtr> induced_rules;  ///< distinct induced rules of that derivation
  sdk::Outcome outcome;                     ///< executed on the world of the query
  std::optional<std::string> error_code;    ///< set when the candidate cannot be accepted
};

/// The last query: everything learning and definitions need.
struct LastQuery {
  std::string text;
  std::vector<std::string> tokens;
  std::string user;
  sdk::ParseResult parse;     ///< all candidates with every derivation
  std::vector<double> probs;  ///< softmax over all candidates' scores
  std::vector<ShownCandidate> shown;
  sdk::WorldState world;  ///< the world the query was answered in
};

struct QueryRequest {
  std::string text;               ///< the utterance (input.max_chars code points at most)
  std::optional<std::int64_t> k;  ///< candidates to show (session.k when unset); not negative
};

struct QueryResult {
  /// The query as the session keeps it for `accept` and `define` (shared: it stays valid after
  /// the session moves on).
  std::shared_ptr<const LastQuery> query;
  const char* status = "unparsable";  ///< "core", "induced" or "unparsable"
  double ms = 0;                      ///< wall time of the query
  /// Distinct readings found; `query->shown` holds the first k.
  std::size_t total() const { return query->parse.candidates.size(); }
};

struct AcceptRequest {
  std::int64_t rank = 0;  ///< index into the last query's shown candidates
};

struct AcceptResult {
  sdk::Outcome outcome;  ///< the accepted program run again on the current world: its new world
};

}  // namespace flipper::kernel

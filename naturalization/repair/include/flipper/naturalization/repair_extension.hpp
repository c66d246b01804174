#pragma once
/// @file repair_extension.hpp
/// Answers that repair (docs/protocol.md § "Repairs") as a session extension above the kernel
/// (docs/architecture.md §3): the kernel's session parses and answers; this module asks the
/// session's parser for the chart of an utterance nothing parsed and for edited sentences
/// (repair.hpp), and writes the "repair" member of a query answer that asked for it. Front ends
/// that call the typed service ask repair_query() after Session::query.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/naturalization/repair.hpp"
#include "flipper/naturalization/unrealizable.hpp"

namespace flipper::naturalization {

/// A repair asks which words `user`'s parses may know beyond the core grammar's: a subscriber
/// appends the words of the rules visible to that user (the lexicon does).
struct VocabularyAsked {
  const std::string& user;
  std::vector<std::string>& words;
};

/// Every word the session's current user's parses may know: the core grammar's terminals, its
/// colour, shape and direction words, and what VocabularyAsked subscribers add (sorted, unique).
std::vector<std::string> vocabulary(const kernel::Session& session);

/// The repair of an answered query nothing parsed (null when it has candidates): the session's
/// parse asked for its chart, and edited sentences parsed with the same scorer, rules and
/// limits (a stopped parse throws deadline_exceeded, "repairing"). Call it right after the query,
/// within the same call's limits.
std::shared_ptr<const Repair> repair_query(kernel::Session& session,
                                           const kernel::QueryResult& result);

/// An unrealizable candidate of an answered query, explained (unrealizable.hpp).
struct ExplainedCandidate {
  std::size_t rank = 0;  ///< its rank in the answer
  Unrealizable explanation;
};

/// Every shown candidate of `result` (the first `first` of them) that is not realizable in the
/// query's world (not run out of a budget, not refused from a plugin), explained with the
/// session's executor, the query's world and the call's limits (deadline_exceeded is thrown).
/// Call it right after the query.
std::vector<ExplainedCandidate> explain_unrealizable(const kernel::Session& session,
                                                     const kernel::QueryResult& result,
                                                     std::size_t first = SIZE_MAX);

/// The protocol's "repair" member (docs/protocol.md "Repairs") as JSON, for front ends that call
/// the typed service and print their own answers (`flipper run --json`): the same fields the
/// query op writes.
kernel::Json repair_json(const Repair& repair);
/// `{"unrealizable": [...]}` for explained candidates in a world of `dims` dimensions.
kernel::Json unrealizable_json(const std::vector<ExplainedCandidate>& explained, int dims);

/// The protocol side: a query op with `"repair": true` (false and null: none; anything else:
/// bad_request before the query runs) gets the member "repair" when nothing parsed, or when some
/// shown candidate is unrealizable (`{"unrealizable": [...]}`).
class RepairExtension final : public kernel::SessionExtension {
 public:
  void attach(kernel::Session& session) override;
};

}  // namespace flipper::naturalization

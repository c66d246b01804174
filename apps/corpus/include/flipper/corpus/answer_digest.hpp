#pragma once
/// @file answer_digest.hpp
/// What a study recording hashes of each protocol answer (docs/studio.md §7, exchanges.jsonl):
/// the answer's text with every `,"ms":NUMBER` member removed, `ms` being the one timing field of
/// the protocol's answers. Inside a JSON string the quotes would be escaped, so the pattern never
/// matches there. The studio hashes this text as it records; `flipper replay verify` hashes its
/// own answer the same way and compares (docs/experiments.md §8).

#include <string>
#include <string_view>

namespace flipper::corpus {

/// `answer` without its `,"ms":NUMBER` members.
std::string answer_for_digest(std::string_view answer);

}  // namespace flipper::corpus

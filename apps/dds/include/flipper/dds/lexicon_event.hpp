#pragma once
/// @file lexicon_event.hpp
/// One replicated lexicon change (idl/flipper/msg/LexiconEvent.idl) as a C++ value, with the
/// checks a received sample must pass before anything is applied.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace flipper::dds {

struct LexiconEvent {
  std::string site;
  std::uint64_t version = 0;
  std::string kind;  ///< "define" | "delete"
  std::uint64_t lamport = 0;
  std::int64_t time = 0;
  std::string author;
  std::string head;
  std::vector<std::string> body;
  std::vector<int> ranks;
  std::string world;               ///< world JSON the definition was made in ("" = none)
  std::vector<std::string> rules;  ///< the origin's rules, "lhs -> rhs => semantics"
  std::string target_site;
  std::uint64_t target_version = 0;
  std::string target_rule;
  std::string certificate;  ///< PEM of the origin site's certificate (DDS Security on)
  std::string signature;    ///< the origin site's signature over signed_text() (bytes)

  /// (lamport, site): orders conflicting definitions of one head across sites.
  bool wins_over(const LexiconEvent& other) const {
    return lamport != other.lamport ? lamport > other.lamport : site > other.site;
  }
  std::string identity() const { return site + "#" + std::to_string(version); }
};

/// Why a received event is malformed, or nothing when it may be applied.
std::optional<std::string> malformed(const LexiconEvent& e);

/// The event as JSON, every field (the signature in hex), and back (throws on a bad object).
nlohmann::json to_json(const LexiconEvent& e);
LexiconEvent event_from_json(const nlohmann::json& j);
/// What a site signs: the JSON of every field but certificate and signature, keys sorted.
std::string signed_text(const LexiconEvent& e);

}  // namespace flipper::dds

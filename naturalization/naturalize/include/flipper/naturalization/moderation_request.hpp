#pragma once
/// @file moderation_request.hpp
/// A moderation (docs/naturalization.md §5 "Moderation") as a request and its answer: the form in
/// which a study's recording keeps a researcher's approve or reject among the protocol exchanges
/// (docs/studio.md §7, `exchanges.jsonl`, origin `researcher`), so that `flipper replay verify`
/// applies it exactly where the group's kernel did.

#include <string>

#include "flipper/naturalization/naturalizer.hpp"

namespace flipper::naturalization {

/// The request text of a moderation: `{"op":"approve","id":ID}` or
/// `{"op":"reject","id":ID,"reason":R}` (no `reason` when it is empty).
std::string moderation_request(bool approve, const std::string& id, const std::string& reason);

/// Applies a moderation request to `naturalizer` as `moderator` and returns its answer text:
/// `{"id":ID,"ok":true,"op":OP}`, plus `"rules":[rule ids]` for an approve. Throws what
/// Naturalizer::approve and reject throw (not_found for an id that is not held), and bad_request
/// for a request that is not one of the two forms above.
std::string apply_moderation(Naturalizer& naturalizer, const std::string& moderator,
                             const std::string& request);

}  // namespace flipper::naturalization

#pragma once
/// @file raw_members.hpp
/// The top-level members of a JSON object text, found without parsing it into a tree: the session
/// echoes a request's "id" as sent and splits a world plugin's text around its "items" and
/// "robot" values (kernel/session world_texts.hpp). Views into the text; nothing is copied. And
/// the nesting depth of a text, without a parse.
#include <cstddef>
#include <string_view>
#include <vector>

namespace flipper::toolkit::json {

/// One top-level member of a JSON object text: the key as written (with its quotes) and the
/// value's raw text.
struct RawMember {
  std::string_view key;
  std::string_view value;
};
/// The top-level members of the JSON object `text`, in order. `text` must be valid JSON (it is
/// not validated); anything else gives an empty list.
std::vector<RawMember> top_level_members(std::string_view text);
/// The raw value of the (last) member `"key"`, or an empty view.
std::string_view top_level_value(std::string_view text, std::string_view key);
/// Depth of the deepest array/object nesting in JSON text (strings skipped), stopping early once
/// it exceeds `stop_above`: no recursion, O(length) (the session refuses a request nested deeper
/// than input.max_json_depth before it is parsed).
int json_depth(std::string_view text, int stop_above);

}  // namespace flipper::toolkit::json

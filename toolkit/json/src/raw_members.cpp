// Top-level members of a JSON object text, found without parsing it (raw_members.hpp).
#include "flipper/toolkit/json/raw_members.hpp"

namespace flipper::toolkit::json {
namespace {

std::size_t skip_space(std::string_view t, std::size_t i) {
  while (i < t.size() && (t[i] == ' ' || t[i] == '\t' || t[i] == '\n' || t[i] == '\r')) ++i;
  return i;
}

// End (one past) of the string starting at t[i] == '"'.
std::size_t skip_string(std::string_view t, std::size_t i) {
  for (++i; i < t.size(); ++i) {
    if (t[i] == '\\')
      ++i;
    else if (t[i] == '"')
      return i + 1;
  }
  return std::string_view::npos;
}

// End (one past) of the value starting at t[i].
std::size_t skip_value(std::string_view t, std::size_t i) {
  if (i >= t.size()) return std::string_view::npos;
  if (t[i] == '"') return skip_string(t, i);
  if (t[i] == '{' || t[i] == '[') {
    int depth = 0;
    for (; i < t.size(); ++i) {
      const char c = t[i];
      if (c == '"') {
        i = skip_string(t, i);
        if (i == std::string_view::npos) return i;
        --i;
      } else if (c == '{' || c == '[') {
        ++depth;
      } else if (c == '}' || c == ']') {
        if (--depth == 0) return i + 1;
      }
    }
    return std::string_view::npos;
  }
  while (i < t.size() && t[i] != ',' && t[i] != '}' && t[i] != ']' && t[i] != ' ' && t[i] != '\n' &&
         t[i] != '\t' && t[i] != '\r')
    ++i;
  return i;
}

}  // namespace

std::vector<RawMember> top_level_members(std::string_view t) {
  std::vector<RawMember> out;
  std::size_t i = skip_space(t, 0);
  if (i >= t.size() || t[i] != '{') return {};
  i = skip_space(t, i + 1);
  if (i < t.size() && t[i] == '}') return out;
  while (i < t.size()) {
    if (t[i] != '"') return {};
    const std::size_t key_end = skip_string(t, i);
    if (key_end == std::string_view::npos) return {};
    std::string_view key = t.substr(i, key_end - i);
    i = skip_space(t, key_end);
    if (i >= t.size() || t[i] != ':') return {};
    i = skip_space(t, i + 1);
    const std::size_t value_end = skip_value(t, i);
    if (value_end == std::string_view::npos) return {};
    out.push_back({key, t.substr(i, value_end - i)});
    i = skip_space(t, value_end);
    if (i < t.size() && t[i] == '}') return out;
    if (i >= t.size() || t[i] != ',') return {};
    i = skip_space(t, i + 1);
  }
  return {};
}

std::string_view top_level_value(std::string_view text, std::string_view key) {
  std::string_view found;
  for (const auto& m : top_level_members(text)) {
    // An escaped key may spell `key` in a way only a JSON parser sees: leave those to it.
    if (m.key.find('\\') != std::string_view::npos) return {};
    if (m.key.size() == key.size() + 2 && m.key.substr(1, key.size()) == key) found = m.value;
  }
  return found;
}

int json_depth(std::string_view text, int stop_above) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (char c : text) {
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > deepest && (deepest = depth) > stop_above) return deepest;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

}  // namespace flipper::toolkit::json

// Input limits from the config, and the nesting depth of a request.
#include "flipper/kernel/limits.hpp"

#include "flipper/kernel/config.hpp"

namespace flipper::kernel {

InputLimits InputLimits::from_config(const Config& c) {
  InputLimits l;
  l.max_line_bytes = static_cast<std::uint64_t>(c.get(keys::kMaxLineBytes));
  l.max_json_depth = static_cast<int>(c.get(keys::kMaxJsonDepth));
  l.max_tokens = static_cast<std::size_t>(c.get(keys::kMaxTokens));
  l.max_body_lines = static_cast<std::size_t>(c.get(keys::kMaxBodyLines));
  l.max_file_bytes = static_cast<std::uint64_t>(c.get(keys::kMaxFileBytes));
  l.max_world_cells = static_cast<std::uint64_t>(c.get(keys::kMaxWorldCells));
  l.cpu_budget = std::chrono::milliseconds(c.get(keys::kCpuBudgetMs));
  l.deadline = std::chrono::milliseconds(c.get(keys::kDeadlineMs));
  return l;
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

}  // namespace flipper::kernel

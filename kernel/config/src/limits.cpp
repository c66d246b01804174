// Input limits from the config.
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

}  // namespace flipper::kernel

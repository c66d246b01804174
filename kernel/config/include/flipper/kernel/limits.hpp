#pragma once
/// @file limits.hpp
/// Limits on what a user or a file may make the kernel do (docs/bad-input.md): every limit is a
/// config key with a documented default, and every refusal has a stable code (sdk::codes).

#include <chrono>
#include <cstdint>
#include <string>

#include "flipper/kernel/keys.hpp"

namespace flipper::kernel {

class Config;

/// Defaults from keys.hpp (one place).
struct InputLimits {
  /// input.max_line_bytes: one request line
  std::uint64_t max_line_bytes = static_cast<std::uint64_t>(keys::kMaxLineBytes.def);
  /// input.max_json_depth: nesting of a request
  int max_json_depth = static_cast<int>(keys::kMaxJsonDepth.def);
  /// input.max_tokens: query, head, each body line
  std::size_t max_tokens = static_cast<std::size_t>(keys::kMaxTokens.def);
  /// input.max_body_lines: lines of a definition
  std::size_t max_body_lines = static_cast<std::size_t>(keys::kMaxBodyLines.def);
  /// input.max_file_bytes: world/grammar/preload files
  std::uint64_t max_file_bytes = static_cast<std::uint64_t>(keys::kMaxFileBytes.def);
  std::uint64_t max_world_cells = static_cast<std::uint64_t>(keys::kMaxWorldCells.def);
  /// session.cpu_budget_ms: CPU time of one request on its thread, end to end
  std::chrono::milliseconds cpu_budget{keys::kCpuBudgetMs.def};
  /// session.deadline_ms: the wall-clock backstop of one request, end to end
  std::chrono::milliseconds deadline{keys::kDeadlineMs.def};

  /// From a validated config (every key present: the schema filled the defaults).
  static InputLimits from_config(const Config& config);
};

}  // namespace flipper::kernel

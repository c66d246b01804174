#pragma once
/// @file keys.hpp
/// The kernel's typed config keys whose defaults code needs: each declared once, here. The
/// config schema (schema.cpp) builds its rows from these declarations, and the option structs
/// (ExecLimits, InputLimits, SessionOptions, ...) take their initial values from them, so a
/// default lives in one place; configs/default.yaml restates none of them (`flipper config
/// check` prints the effective values).

#include <cstdint>
#include <string_view>

namespace flipper::kernel::keys {

/// An integer key: dotted path, default, inclusive range.
struct Int {
  std::string_view path;
  std::int64_t def;
  std::int64_t min;
  std::int64_t max;
};

inline constexpr Int kSessionK{"session.k", 3, 1, 1000};
inline constexpr Int kDeadlineMs{"session.deadline_ms", 5000, 1, 86400000};
inline constexpr Int kActionBudget{"execution.action_budget", 100000, 1, 1000000000000};
inline constexpr Int kTimeBudgetMs{"execution.time_budget_ms", 2000, 1, 86400000};
inline constexpr Int kWhileLimit{"execution.while_limit", 20, 0, 1000000};
inline constexpr Int kMaxChars{"input.max_chars", 2000, 1, 100000000};
inline constexpr Int kMaxSemicolons{"input.max_semicolons", 30, 1, 1000000};
inline constexpr Int kMaxLineBytes{"input.max_line_bytes", 1048576, 64, 1073741824};
inline constexpr Int kMaxJsonDepth{"input.max_json_depth", 64, 2, 10000};
inline constexpr Int kMaxTokens{"input.max_tokens", 400, 1, 65534};
inline constexpr Int kMaxBodyLines{"input.max_body_lines", 100, 1, 100000};
inline constexpr Int kMaxFileBytes{"input.max_file_bytes", 67108864, 1, 1099511627776};
inline constexpr Int kMaxWorldCells{"world.max_cells", 4194304, 1, 268435456};
inline constexpr Int kBusyTimeoutMs{"lexicon.busy_timeout_ms", 10000, 1, 600000};
inline constexpr Int kSnapshotMinRules{"lexicon.snapshot_min_rules", 512, 0, 1000000000};
inline constexpr Int kPerturbedChecks{"induction.perturbed_checks", 0, 0, 1000};

}  // namespace flipper::kernel::keys

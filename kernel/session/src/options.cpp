// Session settings from the config (defaults per docs/core-language.md §9 when a key is absent).
#include "flipper/kernel/session.hpp"

namespace flipper::kernel {
namespace {

std::int64_t int_or(const Config& c, const char* key, std::int64_t fallback) {
  return c.has(key) ? c.get_int(key) : fallback;
}

}  // namespace

SessionOptions SessionOptions::from_config(const Config& c) {
  SessionOptions o;
  o.k = static_cast<int>(int_or(c, "session.k", o.k));
  o.max_chars = static_cast<std::size_t>(int_or(c, "input.max_chars", 2000));
  o.max_semicolons = static_cast<int>(int_or(c, "input.max_semicolons", o.max_semicolons));
  o.limits.action_budget = static_cast<std::uint64_t>(
      int_or(c, "execution.action_budget", static_cast<std::int64_t>(o.limits.action_budget)));
  o.limits.time_budget = std::chrono::milliseconds(
      int_or(c, "execution.time_budget_ms", o.limits.time_budget.count()));
  o.limits.while_limit = static_cast<int>(int_or(c, "execution.while_limit", o.limits.while_limit));
  o.input = InputLimits::from_config(c);
  o.max_chars = static_cast<std::size_t>(int_or(c, "input.max_chars", 2000));
  return o;
}

}  // namespace flipper::kernel

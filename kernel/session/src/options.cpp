// Session settings from a validated config: every key is present (the schema filled the
// defaults, keys.hpp), so nothing here restates a default.
#include "flipper/kernel/keys.hpp"
#include "flipper/kernel/session.hpp"
#include "flipper/language/keys.hpp"

namespace flipper::kernel {

SessionOptions SessionOptions::from_config(const Config& c) {
  const auto get = [&](const keys::Int& k) { return c.get(k); };
  SessionOptions o;
  o.k = static_cast<int>(get(keys::kSessionK));
  o.max_chars = static_cast<std::size_t>(get(keys::kMaxChars));
  o.max_semicolons = static_cast<int>(get(keys::kMaxSemicolons));
  o.limits.action_budget = static_cast<std::uint64_t>(get(language::keys::kActionBudget));
  o.limits.step_budget = static_cast<std::uint64_t>(get(language::keys::kStepBudget));
  o.limits.cpu_budget = std::chrono::milliseconds(get(language::keys::kExecCpuBudgetMs));
  o.limits.deadline = std::chrono::milliseconds(get(language::keys::kExecDeadlineMs));
  o.limits.while_limit = static_cast<int>(get(language::keys::kWhileLimit));
  o.input = InputLimits::from_config(c);
  return o;
}

}  // namespace flipper::kernel

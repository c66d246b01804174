// Conflicts before they happen (docs/naturalization.md §5 "Conflicts"): before a definition is
// stored, the phrases other users already rely on — the heads and body lines of their live rules —
// that the new rules would give another first reading or one more reading.
#include <algorithm>
#include <functional>
#include <set>
#include <unordered_set>

#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::naturalization {

ConflictPolicy parse_conflict_policy(const std::string& text) {
  if (text == "warn") return ConflictPolicy::warn;
  if (text == "refuse") return ConflictPolicy::refuse;
  throw sdk::Error(sdk::codes::kBadConfig,
                   "lexicon.conflicts must be warn or refuse, got '" + text + "'");
}

namespace {

/// Whether a phrase with these tokens can use `rule`: every token the rule's right-hand side
/// spells must occur in it (a derivation consumes them; skipping words never adds one).
bool could_use(const sdk::Rule& rule, const std::unordered_set<std::string>& tokens) {
  return std::all_of(rule.rhs.begin(), rule.rhs.end(), [&](const sdk::Symbol& s) {
    return s.type != sdk::Symbol::Type::token || tokens.count(s.text) > 0;
  });
}

/// A parse's first reading as text (empty: none) and how many readings it has.
struct Reading {
  std::string first;
  std::size_t total = 0;
};

Reading read_phrase(const sdk::ParseResult& result) {
  Reading r;
  r.total = result.candidates.size();
  if (!result.candidates.empty()) r.first = sdk::render(result.candidates.front().program);
  return r;
}

}  // namespace

std::vector<DefineConflict> Naturalizer::find_conflicts(
    const std::string& author, const std::vector<std::shared_ptr<sdk::Rule>>& fresh,
    const sdk::StopCondition& stop) {
  std::vector<DefineConflict> out;
  // Only a shared lexicon lets one user's rules reach another's parses.
  if (options_.sharing != Sharing::shared || fresh.empty()) return out;
  // The phrases, newest rules first, each (phrase, user) once, bounded.
  struct Probe {
    std::string phrase, user;
  };
  std::vector<Probe> probes;
  std::set<std::pair<std::string, std::string>> seen;
  for (auto it = rules_.rbegin(); it != rules_.rend() && probes.size() < kMaxConflictProbes; ++it) {
    const sdk::Rule& r = **it;
    if (r.author == author) continue;
    std::vector<std::string> phrases{r.head};
    phrases.insert(phrases.end(), r.body.begin(), r.body.end());
    for (auto& p : phrases) {
      const auto tokens = sdk::tokenize(p);
      const std::unordered_set<std::string> set(tokens.begin(), tokens.end());
      const bool reachable = std::any_of(fresh.begin(), fresh.end(),
                                         [&](const auto& f) { return could_use(*f, set); });
      if (!reachable || tokens.empty() || !seen.emplace(p, r.author).second) continue;
      probes.push_back({std::move(p), r.author});
      if (probes.size() >= kMaxConflictProbes) break;
    }
  }
  if (probes.empty()) return out;

  // The probes' parses as one series (kernel::checked_parses: one child process when the parser
  // is isolated), read in order; each probe parses with what its user sees.
  std::vector<std::function<bool(const sdk::Rule&)>> visibility;
  visibility.reserve(probes.size());
  for (const auto& probe : probes) visibility.push_back(visibility_for(probe.user));
  std::vector<sdk::ParseRequest> requests(probes.size());
  for (std::size_t i = 0; i < probes.size(); ++i) {
    sdk::ParseRequest& req = requests[i];
    req.tokens = sdk::tokenize(probes[i].phrase);
    req.scorer = runtime_->scorer.borrow();  // covered by the parse calls that use it
    req.context.user = probes[i].user;
    req.context.usage = runtime_->usage.get();
    req.visible = sdk::RuleFilter::of(visibility[i]);  // outlives the parses below
    req.beam = options_.induction.beam;
    req.stop = stop;
  }
  const auto parse_all = [&] {
    std::vector<kernel::ParseOutcome> outcomes =
        kernel::checked_parses(runtime_->parser, requests, stop);  // docs/plugins-untrusted.md
    std::vector<Reading> readings;
    readings.reserve(outcomes.size());
    for (auto& o : outcomes) {
      if (o.error) std::rethrow_exception(o.error);
      if (o.result.stopped) {
        const sdk::StopCause cause =
            stop.cause() != sdk::StopCause::none ? stop.cause() : sdk::StopCause::cpu_budget;
        throw sdk::StoppedError(cause,
                                std::string("deadline exceeded while checking the definition "
                                            "for conflicts (stopped: ") +
                                    sdk::to_string(cause) +
                                    ": session.cpu_budget_ms or session.deadline_ms); "
                                    "nothing was stored");
      }
      readings.push_back(read_phrase(o.result));
    }
    return readings;
  };
  const std::vector<Reading> before = parse_all();

  // The new rules join the grammar for the second parse only, after every stored rule (as they
  // would be committed), and leave it whatever happens.
  std::int64_t created = rules_.empty() ? 0 : rules_.back()->created;
  std::vector<std::string> added;
  struct Remove {
    Naturalizer& self;
    std::vector<std::string>& ids;
    ~Remove() {
      for (const auto& id : ids)
        self.runtime_->parser.call("remove_rule", [&](sdk::Parser& p) { p.remove_rule(id); });
    }
  } remove{*this, added};
  for (const auto& f : fresh) {
    auto pending = std::make_shared<sdk::Rule>(*f);
    pending->id = "pending:" + std::to_string(added.size() + 1);
    pending->created = ++created;
    runtime_->parser.call("add_rule", [&](sdk::Parser& p) { p.add_rule(pending); });
    added.push_back(pending->id);
  }
  const std::vector<Reading> after_all = parse_all();
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Reading& after = after_all[i];
    if (after.first != before[i].first)
      out.push_back({probes[i].phrase, probes[i].user, "first_reading", before[i].first,
                     after.first, before[i].total, after.total});
    else if (after.total > before[i].total)
      out.push_back({probes[i].phrase, probes[i].user, "new_reading", before[i].first, after.first,
                     before[i].total, after.total});
  }
  return out;
}

}  // namespace flipper::naturalization

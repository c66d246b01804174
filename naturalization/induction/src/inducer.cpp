// The §4 pipeline: checks, body program, head chart, packings, rules.
#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/naturalization/induction.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

#include <utility>

namespace flipper::naturalization {

Inducer::Inducer(kernel::PluginRef<const sdk::Parser> parser,
                 kernel::PluginRef<const sdk::Scorer> scorer, InductionOptions options,
                 const sdk::UsageCounters* usage)
    : parser_(std::move(parser)), scorer_(std::move(scorer)), options_(options), usage_(usage) {}

namespace {

// A body line given with its program (DefinitionInput::body_programs): the parser's candidate
// with that program when the line reads so, else the program alone (no derivation to align).
void take_program_line(const sdk::Program& program, sdk::ParseResult& parsed,
                       std::vector<sdk::Program>& lines, PreparedDefinition& out) {
  sdk::Candidate chosen;
  for (auto& c : parsed.candidates)
    if (sdk::equal(c.program, program)) {
      chosen = std::move(c);
      break;
    }
  if (!chosen.program) chosen.program = program;
  lines.push_back(chosen.program);
  out.body_derivations.push_back(chosen.derivations.empty() ? nullptr : chosen.derivations[0]);
  out.body_candidates.push_back(std::move(chosen));
}

std::size_t node_count(const sdk::Derivation& d) {
  std::size_t n = 1;
  for (const auto& k : d.kids)
    if (k) n += node_count(*k);
  return n;
}

// The derivation of a body line that the February 2018 runs aligned (docs/naturalization.md
// §4.8): of those giving the line's program, the one with the fewest nodes (the first such), so a
// phrase the lexicon reads word for word is read whole, with no node inside.
sdk::DerivationPtr fewest_nodes(const sdk::Candidate& line) {
  sdk::DerivationPtr best;
  std::size_t best_count = 0;
  for (const auto& d : line.derivations) {
    if (!d) continue;
    const std::size_t count = node_count(*d);
    if (!best || count < best_count) {
      best = d;
      best_count = count;
    }
  }
  return best;
}

}  // namespace

PreparedDefinition Inducer::prepare(const DefinitionInput& def,
                                    const std::function<bool(const sdk::Rule&)>& visible,
                                    const sdk::StopCondition& stop) const {
  PreparedDefinition out;
  out.head_tokens = sdk::tokenize(def.head);
  if (out.head_tokens.empty())
    throw sdk::Error(induction_codes::kEmptyHead, "the head of a definition must have a word");
  if (def.body.empty())
    throw sdk::Error(sdk::codes::kBadRequest, "the body of a definition needs at least one line");

  sdk::ParseRequest req;
  req.scorer = scorer_.borrow();  // covered by the parse call that uses it
  req.context.user = def.author;
  req.context.usage = usage_;
  req.visible = sdk::RuleFilter::of(visible);  // `visible` outlives every parse below
  req.beam = options_.beam;
  req.stop = stop;
  auto refuse_if_stopped = [&](const sdk::ParseResult& r, const std::string& what) {
    if (r.stopped) {
      const sdk::StopCause cause = stop.cause();
      throw sdk::StoppedError(cause, "deadline exceeded while parsing " + what +
                                         " of the definition (stopped: " + sdk::to_string(cause) +
                                         ": session.cpu_budget_ms or session.deadline_ms)");
    }
  };

  // One parse of the head gives both the core check (whole span) and the head chart; then one
  // parse per body line that has words. They are made as one series (kernel::checked_parses:
  // one child process when the parser is isolated) and read in order, so that each refusal
  // below comes where it would if each parse were made after the lines before it were read.
  std::vector<sdk::ParseRequest> requests;
  requests.reserve(def.body.size() + 1);
  req.tokens = out.head_tokens;
  req.want_chart = true;
  req.whole_span = true;
  requests.push_back(req);
  req.want_chart = false;
  std::vector<std::vector<std::string>> body_tokens;
  body_tokens.reserve(def.body.size());
  for (const auto& text : def.body) {
    body_tokens.push_back(sdk::tokenize(text));
    if (body_tokens.back().empty()) continue;
    req.tokens = body_tokens.back();
    requests.push_back(req);
  }
  std::vector<kernel::ParseOutcome> outcomes =
      kernel::checked_parses(parser_, requests, stop);  // docs/plugins-untrusted.md
  std::size_t next = 0;
  auto parsed = [&]() -> sdk::ParseResult& {
    kernel::ParseOutcome& o = outcomes.at(next++);  // a series ends only at a failure
    if (o.error) std::rethrow_exception(o.error);
    return o.result;
  };
  sdk::ParseResult& head = parsed();
  refuse_if_stopped(head, "the head");
  for (const auto& c : head.candidates)
    if (c.core_only)
      throw sdk::Error(induction_codes::kHeadIsCore, "'" + def.head + "' already means " +
                                                         sdk::render(c.program) +
                                                         " in the core language; use it as it is");
  out.head_chart = std::move(head.chart);

  std::vector<sdk::Program> lines;
  for (std::size_t i = 0; i < def.body.size(); ++i) {
    std::vector<std::string>& tokens = body_tokens[i];
    const std::string line = "body line " + std::to_string(i + 1) + " '" + def.body[i] + "'";
    sdk::ParseResult none;
    sdk::ParseResult& r = tokens.empty() ? none : parsed();
    refuse_if_stopped(r, "body line " + std::to_string(i + 1));
    if (i < def.body_programs.size() && def.body_programs[i]) {
      take_program_line(def.body_programs[i], r, lines, out);
      out.body_tokens.push_back(std::move(tokens));
      continue;
    }
    if (r.candidates.empty())
      throw sdk::Error(induction_codes::kBodyUnparsable, line + " does not parse");
    const int rank = i < def.body_ranks.size() ? def.body_ranks[i] : 0;
    if (rank < 0 || static_cast<std::size_t>(rank) >= r.candidates.size())
      throw sdk::Error(sdk::codes::kBadRequest, line + " has no candidate of rank " +
                                                    std::to_string(rank) + " (it has " +
                                                    std::to_string(r.candidates.size()) + ")");
    sdk::Candidate& chosen = r.candidates[static_cast<std::size_t>(rank)];
    lines.push_back(chosen.program);
    out.body_derivations.push_back(chosen.derivations.empty() ? nullptr : chosen.derivations[0]);
    out.body_tokens.push_back(std::move(tokens));
    out.body_candidates.push_back(std::move(chosen));
  }
  out.body = sdk::make_seq(std::move(lines));
  return out;
}

InductionResult Inducer::induce(const PreparedDefinition& p, const sdk::Program& winner,
                                bool winner_is_rewriting,
                                const std::function<bool(const sdk::Rule&)>& exists) const {
  InductionResult out;
  const int n = static_cast<int>(p.head_tokens.size());
  auto add = [&](sdk::Rule rule) {
    // One meaning per RHS within a definition; window alignment's rules, one per category
    // (docs/naturalization.md §4.8).
    const bool per_category = options_.alignment_window && rule.how == sdk::RuleOrigin::alignment;
    for (const auto& r : out.rules)
      if (r.rhs == rule.rhs && (!per_category || r.lhs == rule.lhs)) return;
    if (exists && exists(rule)) return;
    out.rules.push_back(std::move(rule));
  };

  // Simple packing of the user's body.
  // The February 2018 runs never packed a packed alignment rule (§4.8).
  const bool packed_alignment = !options_.alignment_window;
  const std::vector<Match> body_matches = find_matches(p.head_chart, p.body, n, packed_alignment);
  out.simple = simple_packing(body_matches);
  const std::string lhs = sdk::normalize_category(category_of_sort(p.body->sort));
  if (auto built = build_rule(lhs, p.head_tokens, out.simple, p.body, sdk::RuleOrigin::simple);
      built.rule)
    add(std::move(*built.rule));

  // Best packing of the winner (the body unless a rewriting beat it).
  out.matches =
      winner_is_rewriting ? find_matches(p.head_chart, winner, n, packed_alignment) : body_matches;
  out.best = best_packing(out.matches, n);
  const auto how = winner_is_rewriting ? sdk::RuleOrigin::rewriting : sdk::RuleOrigin::best;
  if (auto built = build_rule(sdk::normalize_category(category_of_sort(winner->sort)),
                              p.head_tokens, out.best, winner, how);
      built.rule)
    add(std::move(*built.rule));

  if (options_.alignment && p.body_tokens.size() == 1 && p.body_derivations[0]) {
    auto rules = options_.alignment_window
                     ? window_alignment_rules(p.head_tokens, p.body_tokens[0],
                                              fewest_nodes(p.body_candidates[0]), p.head_chart, 4)
                     : alignment_rules(p.head_tokens, p.body_tokens[0], p.body_derivations[0], 4);
    for (auto& r : rules) add(std::move(r));
  }
  return out;
}

}  // namespace flipper::naturalization

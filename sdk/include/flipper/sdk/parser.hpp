#pragma once
/// @file parser.hpp
/// Parser plugins: utterance tokens -> ranked candidates (docs/naturalization.md §2).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "flipper/sdk/derivation.hpp"
#include "flipper/sdk/export.hpp"
#include "flipper/sdk/grammar.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/sdk/scorer.hpp"

namespace flipper::sdk {
inline namespace v1 {

struct ParseRequest {
  std::vector<std::string> tokens;  ///< from flipper::sdk::tokenize
  ScoreContext context;             ///< tokens pointer is set by the parser if null
  const Scorer* scorer = nullptr;   ///< required
  /// Which rules may be used (sharing modes); null means every rule.
  std::function<bool(const Rule&)> visible;
  int beam = 0;             ///< derivations kept per (category, span); 0 = plugin default
  bool want_chart = false;  ///< also return every derivation of every proper sub-span
  bool whole_span = true;   ///< false: no root candidates needed (head charts)
  /// When to give up: the caller's deadline, cancel flag and derivation budget. The
  /// wrapper Parser::parse does not call the plugin when it has already fired and marks the
  /// result `stopped` when it fired during the parse; a plugin polls `should_stop(derivations)`
  /// in its inner loops (every few thousand steps at most) and returns what it has.
  StopCondition stop;
};

struct ParseResult {
  /// Distinct programs over the whole utterance that pass the loop-variable check, ordered:
  /// core candidates first, then by score (desc), then by creation order of the newest rule.
  std::vector<Candidate> candidates;
  /// With want_chart: derivations of every span except the whole utterance, every category.
  std::vector<DerivationPtr> chart;
  bool stopped = false;  ///< the stop condition fired; results may be partial (callers refuse)
  std::uint64_t derivations = 0;  ///< derivations built (statistics)
};

class FLIPPER_SDK_API Parser : public Plugin {
 public:
  using Interface = Parser;
  ~Parser() override;

  /// Replaces the grammar (core + induced rules). Indexes it; may be slow-ish.
  void set_grammar(std::shared_ptr<const Grammar> grammar) { do_set_grammar(std::move(grammar)); }
  /// Adds one rule incrementally (a new induced rule).
  void add_rule(RulePtr rule) { do_add_rule(std::move(rule)); }
  /// Removes a rule by id (a deleted induced rule); unknown ids are ignored.
  void remove_rule(const std::string& id) { do_remove_rule(id); }
  /// Parses. Never throws for "no parse": returns no candidates. Honours `request.stop` (see
  /// ParseRequest::stop) even for a plugin that never polls it: a stop that fired before or
  /// during the parse gives `stopped == true`.
  ParseResult parse(const ParseRequest& request) const {
    if (request.stop.should_stop(0)) {
      ParseResult none;
      none.stopped = true;
      return none;
    }
    ParseResult result = do_parse(request);
    if (!result.stopped && request.stop.expired()) result.stopped = true;
    return result;
  }

 protected:
  virtual void do_set_grammar(std::shared_ptr<const Grammar> grammar) = 0;
  virtual void do_add_rule(RulePtr rule) = 0;
  virtual void do_remove_rule(const std::string& id) = 0;
  virtual ParseResult do_parse(const ParseRequest& request) const = 0;
};

template <>
struct KindOf<Parser> {
  static constexpr PluginKind value = PluginKind::parser;
};

}  // namespace v1
}  // namespace flipper::sdk

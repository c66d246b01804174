#pragma once
/// @file parser.hpp
/// Parser plugins: utterance tokens -> ranked candidates (docs/naturalization.md §2).

#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "flipper/sdk/derivation.hpp"
#include "flipper/sdk/export.hpp"
#include "flipper/sdk/grammar.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/sdk/scorer.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// Which rules a parse may use (the lexicon's sharing modes): a plain callback, a function
/// pointer and the context it is called with, so that no std::function (whose layout is the
/// standard library's business) crosses the plugin boundary. An empty filter admits every rule.
/// The caller owns what `context` points to and keeps it alive for the parse.
struct RuleFilter {
  bool (*admits)(const void* context, const Rule& rule) = nullptr;
  const void* context = nullptr;

  /// Whether a filter is set.
  explicit operator bool() const { return admits != nullptr; }
  /// Whether `rule` may be used: true without a filter.
  bool operator()(const Rule& rule) const { return admits == nullptr || admits(context, rule); }
  /// A filter that asks `predicate(rule)`, for a callable that outlives the filter (a lambda
  /// variable, or a std::function the caller keeps: an empty one admits every rule).
  template <class Predicate>
  static RuleFilter of(const Predicate& predicate) {
    if constexpr (std::is_constructible_v<bool, const Predicate&>) {
      if (!static_cast<bool>(predicate)) return {};
    }
    return {[](const void* c, const Rule& rule) -> bool {
              return (*static_cast<const Predicate*>(c))(rule);
            },
            &predicate};
  }
  /// A temporary would be gone before the parse: keep the callable in a variable.
  template <class Predicate>
  static RuleFilter of(const Predicate&& predicate) = delete;
};

struct ParseRequest {
  std::vector<std::string> tokens;  ///< from flipper::sdk::tokenize
  ScoreContext context;             ///< tokens pointer is set by the parser if null
  const Scorer* scorer = nullptr;   ///< required
  /// Which rules may be used (sharing modes); empty means every rule.
  RuleFilter visible;
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

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk

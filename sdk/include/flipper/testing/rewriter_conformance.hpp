#pragma once
/// @file rewriter_conformance.hpp
/// Conformance checks for rewriter plugins (header-only, Catch2 v2). A plugin's test calls
/// `check_rewriter_conformance(plugin, request)` for a few requests of its domain; it checks that
/// - proposing never throws for a valid request;
/// - every proposal is a complete Action program (non-null, sort Action, no template holes,
///   loop variables bound) with a non-empty rewriting name;
/// - proposals are deterministic: the same request gives the same programs, names and order;
/// - proposing without an execution service also works (a rewriter may then propose less).

#include <catch2/catch.hpp>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/rewriter.hpp"

namespace flipper::testing {

inline void check_rewrite_candidates(const std::vector<sdk::RewriteCandidate>& candidates) {
  for (const auto& c : candidates) {
    INFO("rewriting '" << c.rewriting << "' proposed "
                       << (c.program ? sdk::render(c.program) : std::string("(null)")));
    REQUIRE(c.program != nullptr);
    CHECK(c.program->sort == sdk::Sort::Action);
    CHECK_FALSE(sdk::has_holes(c.program));
    CHECK(sdk::loop_variables_bound(c.program));
    CHECK_FALSE(c.rewriting.empty());
  }
}

inline void check_rewriter_conformance(const sdk::Rewriter& rewriter,
                                       const sdk::RewriteRequest& request) {
  std::vector<sdk::RewriteCandidate> first, second;
  REQUIRE_NOTHROW(first = rewriter.propose(request));
  REQUIRE_NOTHROW(second = rewriter.propose(request));
  check_rewrite_candidates(first);
  INFO("proposed twice for the same request: " << first.size() << " then " << second.size()
                                               << " candidates; want the same");
  REQUIRE(first.size() == second.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    INFO("candidate " << i << ": first '" << first[i].rewriting << "', second '"
                      << second[i].rewriting << "'");
    CHECK(sdk::equal(first[i].program, second[i].program));
    CHECK(first[i].rewriting == second[i].rewriting);
  }
  sdk::RewriteRequest blind = request;
  blind.exec = nullptr;
  std::vector<sdk::RewriteCandidate> without_exec;
  INFO("the same request without an executor (exec = null)");
  REQUIRE_NOTHROW(without_exec = rewriter.propose(blind));
  check_rewrite_candidates(without_exec);
}

}  // namespace flipper::testing

#pragma once
/// @file derivation.hpp
/// Derivations (parse trees) and candidates: what a parser produces, a scorer scores and learns
/// from, and the inducer matches against.

#include <memory>
#include <string>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/grammar.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

struct Derivation;
using DerivationPtr = std::shared_ptr<const Derivation>;

/// A node of a parse tree: `rule` applied over tokens [start, end).
struct Derivation {
  RulePtr rule;
  int start = 0;
  int end = 0;
  std::vector<DerivationPtr> kids;  ///< one per RHS category, in RHS order
  Program sem;                      ///< the (sub)program this derivation yields
  double score = 0;                 ///< total score of the subtree (local + kids)
  bool core_only = true;            ///< the subtree uses only core rules
  std::int64_t newest_rule = 0;     ///< max `created` of induced rules used (0 if core only)
  const std::string& category() const { return rule->lhs; }
};

/// One interpretation: a distinct program with every derivation that yields it (best first).
struct Candidate {
  Program program;
  std::vector<DerivationPtr> derivations;
  double score = 0;       ///< best derivation's score
  bool core_only = true;  ///< some derivation of it uses only core rules
  std::int64_t newest_rule = 0;
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk

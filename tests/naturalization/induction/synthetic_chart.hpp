#pragma once
// Hand-built derivations for inducer tests that need no parser.
#include <memory>
#include <string>
#include <vector>

#include "flipper/sdk/derivation.hpp"

namespace flipper::testsupport {

inline sdk::RulePtr rule_for(const std::string& lhs, bool induced = false) {
  auto r = std::make_shared<sdk::Rule>();
  r->lhs = lhs;
  r->induced = induced;
  r->id = lhs;
  return r;
}

inline sdk::DerivationPtr node(const std::string& lhs, int start, int end, sdk::Program sem,
                               double score = 1, std::vector<sdk::DerivationPtr> kids = {},
                               bool core_only = true) {
  auto d = std::make_shared<sdk::Derivation>();
  d->rule = rule_for(lhs, !core_only);
  d->start = start;
  d->end = end;
  d->sem = std::move(sem);
  d->score = score;
  d->core_only = core_only;
  d->kids = std::move(kids);
  return d;
}

}  // namespace flipper::testsupport

#pragma once
/// @file rewriter.hpp
/// Rewriter plugins: propose more general bodies for a definition (docs/naturalization.md §6). The
/// kernel checks each proposal for equivalence and selects; the rewriter only generates.

#include <string>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/export.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

struct RewriteRequest {
  Program body;                            ///< the user's body (one program; lines form a sequence)
  WorldState before;                       ///< the world before the first body line
  const ExecutionService* exec = nullptr;  ///< to learn what the body does
  std::vector<std::string> head_tokens;
};

struct RewriteCandidate {
  Program program;
  std::string
      rewriting;  ///< "loop", "moves_to_visit", "visit_by_predicate", "pick_by_predicate"...
};

class FLIPPER_SDK_API Rewriter : public Plugin {
 public:
  using Interface = Rewriter;
  ~Rewriter() override;
  /// Candidates in generation order (equivalence not yet checked; duplicates allowed).
  std::vector<RewriteCandidate> propose(const RewriteRequest& request) const {
    return do_propose(request);
  }

 protected:
  virtual std::vector<RewriteCandidate> do_propose(const RewriteRequest& request) const = 0;
};

template <>
struct KindOf<Rewriter> {
  static constexpr PluginKind value = PluginKind::rewriter;
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk

#pragma once
// What unrealizable.cpp (the failing step and why) and variants.cpp (the nearest realizable
// variant) share: the counted executor, and paths to a node of a program.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "flipper/naturalization/unrealizable.hpp"

namespace flipper::naturalization::detail {

/// The run budget is spent (what was found so far is the answer).
struct OutOfRuns {};

/// The query's executor with a count: at most `cap` executions; deadline_exceeded is thrown.
class CountedRun {
 public:
  CountedRun(const RunProgram& run, std::size_t cap) : run_(run), cap_(cap) {}
  /// Throws OutOfRuns when `cap` executions were made already.
  sdk::Outcome operator()(const sdk::Program& program, const sdk::WorldState& world);
  std::size_t used() const { return used_; }

 private:
  const RunProgram& run_;
  std::size_t cap_;
  std::size_t used_ = 0;
};

/// Whether an execution did everything it was asked (realizable and no error).
bool realized(const sdk::Outcome& o);

/// Child indices from a program's root to one of its nodes.
using NodePath = std::vector<std::size_t>;

/// `root` with the node at `path` replaced by `with` (the nodes above rebuilt).
sdk::Program replace_at(const sdk::Program& root, const NodePath& path, const sdk::Program& with);

/// The nearest realizable variant: edits of the node at `step` in `program`, each whole edited
/// program executed on `world` (at most kMaxVariantRuns), fewest edits first.
void find_variant(const sdk::Program& program, const NodePath& step, const sdk::WorldState& world,
                  const RunProgram& run, Unrealizable& out);

}  // namespace flipper::naturalization::detail

#pragma once
/// @file predicate_programs.hpp
/// Builders for the programs rewritings 2-4 of docs/naturalization.md §6 propose, and the checks
/// that decide which of them apply to a body.

#include <string>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/execution.hpp"

namespace flipper::plugins::rewrites {

/// An item description: `item`, `item is c`, `item is s` or `item is c and is s`.
struct ItemPredicate {
  std::string color;  ///< empty: no colour test
  std::string shape;  ///< empty: no shape test
  friend bool operator==(const ItemPredicate&, const ItemPredicate&) = default;
};

/// The predicates §6 derives from items seen: for each distinct (colour, shape), in order,
/// `is c`, `is s`, `is c and is s`; duplicates removed; the plain `item` first.
std::vector<ItemPredicate> predicates_for(const std::vector<sdk::ItemInfo>& items);

sdk::Program item_program(const ItemPredicate& p);
/// `visit [x,y]` (or `[x,y,z]` when dims == 3).
sdk::Program visit_cell(const sdk::Cell& cell, int dims);
/// `visit world containing I`.
sdk::Program visit_world_containing(const ItemPredicate& p);
/// `pick I` / `pick every I` (kind Pick) or the same with `drop` (kind Drop).
sdk::Program pick_or_drop(sdk::Kind kind, const ItemPredicate& p, bool every);

/// Whether every statement of `program` is a move (inside sequences and repeats).
bool only_moves(const sdk::Program& program);
/// Whether every primitive statement of `program` is a move or a visit (inside sequences,
/// repeats, strict blocks, conditionals and loops): a visit by predicate replaces all of them.
bool only_movement(const sdk::Program& program);
/// Whether every statement of `program` is a `pick` (kind Pick) or every one a `drop` (Drop),
/// inside sequences, repeats and strict blocks: a pick/drop by predicate replaces all of them.
/// Judged on the program, never on the trace: a visit that moved nothing is still a statement.
bool only_item_actions(const sdk::Program& program, sdk::Kind kind);
/// Whether the trace is non-empty and every step has act `act`.
bool trace_only(const std::vector<sdk::TraceStep>& trace, sdk::TraceStep::Act act);

}  // namespace flipper::plugins::rewrites

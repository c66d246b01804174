#pragma once
/// @file loop_rolling.hpp
/// Rewriting 1 of docs/naturalization.md §6: consecutive repeats of a statement or of a block of
/// statements become `repeat n times ...`, in every sequence of the program, never dropping a
/// statement.

#include <cstddef>

#include "flipper/sdk/ast.hpp"

namespace flipper::plugins::rewrites {

/// Rolls every run of >= 2 consecutive equal blocks (of at most `max_block` statements) into a
/// `repeat`. At each position the run covering the most statements wins (ties: the shorter
/// block); rolled blocks are rolled again inside. Returns `program` itself when nothing rolls.
sdk::Program roll_loops(const sdk::Program& program, std::size_t max_block);

}  // namespace flipper::plugins::rewrites

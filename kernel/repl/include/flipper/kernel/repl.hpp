#pragma once
/// @file repl.hpp
/// The terminal front end for people: a client of the session ops (query, accept, define, world,
/// user, rules, state) that draws the world as a text map and lists candidates with a short plan
/// description. Uses GNU readline (history, line editing) on a terminal and plain line reading
/// otherwise, so it can be scripted and tested.

#include <iosfwd>
#include <memory>
#include <string>

#include "flipper/kernel/session.hpp"

namespace flipper::kernel::repl {

/// The world object as a text map: `##` walls, `R` robot, items as colour+shape letters (`rc` a
/// red circle), `n*` for n items on one cell, y growing upward (top row = max y), axes, and a
/// legend listing items, held items and rooms. 3-D worlds show the robot's z layer.
std::string render_map(const Json& world);

/// One candidate of a query answer, numbered for the user (1-based `number`): canonical text,
/// probability, steps, picks/drops, warnings, induced rules and errors.
std::string describe_candidate(const Json& candidate, int number);

/// Reads lines with a prompt; nullopt at end of input.
class LineReader {
 public:
  virtual ~LineReader() = default;
  virtual bool read(const char* prompt, std::string& line) = 0;
};
/// GNU readline on a terminal (with history), else plain lines from `in` (no prompts echoed).
std::unique_ptr<LineReader> make_line_reader(std::istream& in, bool terminal);

/// Runs the loop until `:quit` or end of input. Returns the process exit status.
int run(Session& session, LineReader& reader, std::ostream& out);

}  // namespace flipper::kernel::repl

#pragma once
/// @file repl.hpp
/// The terminal front end for people: a client of the session ops (query, accept, define, world,
/// user, rules, state) that draws the world as a text map and lists candidates with a short plan
/// description. Uses GNU readline (history, line editing) on a terminal and plain line reading
/// otherwise, so it can be scripted and tested.

#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/naturalization/repair.hpp"
#include "flipper/naturalization/unrealizable.hpp"

namespace flipper::repl {

/// What render_map draws besides the world.
struct MapOptions {
  const kernel::Json* trace =
      nullptr;               ///< protocol trace steps drawn as `o` path, `E` end, `P`/`D`
  bool legend = true;        ///< legend, stacks, other floors, robot and rooms below the grid
  std::optional<int> floor;  ///< 3-D: the z layer shown (default: the robot's)
};

/// The world object as a text map: `##` walls, `R` robot, items as colour+shape letters (`rc` a
/// red circle), `n*` for n items on one cell, y growing upward (top row = max y), axes, and a
/// legend listing items, held items and rooms. 3-D worlds show one floor (labelled with its z),
/// keep z in coordinates and list the items of the other floors.
std::string render_map(const kernel::Json& world, const MapOptions& options = {});

/// One candidate of a query answer, numbered for the user (1-based `number`): canonical text,
/// probability, steps, picks/drops, warnings (repeats collapsed), induced rules and errors.
std::string describe_candidate(const kernel::Json& candidate, int number);

/// Warnings with repeats collapsed, in first-seen order: "28 × move left blocked ...".
std::vector<std::string> collapse_warnings(const kernel::Json& warnings);

/// Words of `tokens` the grammar does not know (not a terminal of `vocabulary`, not a number),
/// each with " (did you mean 'x'?)" when a known word is close, else with what the core language
/// says instead when it is a plain word people try first (plain_word_hint).
std::vector<std::string> unknown_words(const std::vector<std::string>& tokens,
                                       const std::vector<std::string>& vocabulary);
/// " (the core language says 'pick item')" for "take", "grab", ...; "" for other words.
std::string plain_word_hint(const std::string& word);
/// "Unknown words: 'vist' (did you mean 'visit'?), 'go' (the core language says ...)." or "".
std::string unknown_words_note(kernel::Session& session, const std::string& text);

/// A repair (docs/protocol.md "Repairs") as lines for the repl: "Understood: ...",
/// "Not understood: ...", the numbered nearest sentences with their edits, "Teach it: ...";
/// each line only when the repair has it. `teach`: how the last line begins (the repl's
/// command; `flipper run` names the repl it is taught in).
std::string repair_lines(const naturalization::Repair& repair,
                         const std::string& teach = "Teach it: `:define`, then the steps:");
/// The same on one line for an error message: "; nearest understood: 'move up' (drop 'x');
/// understood: ...; not understood: ..." ("" for an empty repair).
std::string repair_summary(const naturalization::Repair& repair);
/// An unrealizable reading explained (docs/naturalization.md §7) on one line: "Cannot be done
/// here: STEP fails at [x,y]: WHY. Nearest that works: FORMULA (EDIT)." or "No variant found
/// (N tried)."
std::string unrealizable_line(const naturalization::Unrealizable& u, int dims);

/// One row of the language guide's example table (docs/language.md).
struct GuideExample {
  std::string construct;  ///< "move one cell"
  std::string example;    ///< "move up"
  std::string result;     ///< "ends at [2,5], 1 move" on the study map
};
/// The guide's examples, in its order (the guide is embedded in the binary).
std::vector<GuideExample> guide_examples();
/// The text of `:examples`.
std::string examples_text();
/// The guide's part of `:help`: every construct of the example table with its example, then the
/// guide's section titles. Built from the embedded guide, so help and guide cannot drift.
std::string guide_help_text();

/// Reads lines with a prompt.
class LineReader {
 public:
  enum class Read {
    line,         ///< `line` holds what was typed
    interrupted,  ///< Ctrl-C: `line` holds the text that was dropped (may be empty)
    end,          ///< end of input (Ctrl-D on an empty line)
  };
  virtual ~LineReader() = default;
  virtual Read read(const char* prompt, std::string& line) = 0;
  /// True (once) when Ctrl-C was pressed since the last call or read, e.g. during a query.
  virtual bool take_interrupt() { return false; }
};
/// GNU readline on a terminal, else plain lines from `in` (no prompts echoed). On a terminal,
/// history is kept in `history_file` (when not empty) across runs, and Ctrl-C (SIGINT) cancels
/// the line being typed instead of ending the program, for as long as the reader lives.
std::unique_ptr<LineReader> make_line_reader(std::istream& in, bool terminal,
                                             const std::string& history_file = {});
/// Where the history lives: $FLIPPER_HISTORY, else ~/.local/share/flipper/repl_history.
std::string default_history_file();

/// Runs the loop until `:quit` or end of input. Returns the process exit status.
int run(kernel::Session& session, LineReader& reader, std::ostream& out);

}  // namespace flipper::repl

#pragma once
// The bad-input table: every class of hostile input, the stable code it gets and an
// excerpt of the message. The tests in test_bad_input.cpp drive build/bin/flipper with each row;
// the "Bad input" table of docs/bad-input.md is rendered from these rows (test_readme_table.cpp
// compares it).
#include <functional>
#include <string>
#include <vector>

namespace flipper::limitstest {

/// Files and directories the rows refer to (made by the test fixture).
struct Scratch {
  std::string dir;            ///< a fresh directory
  std::string fifo;           ///< a FIFO nobody writes to
  std::string many_items;     ///< a world file: 30,000 items on one cell
  std::string big_world;      ///< a world file larger than input.max_file_bytes in the session
  std::string truncated_dir;  ///< a plugin dir holding a truncated copy of astar.so as astar.so
  std::string dup_config;     ///< a config file with `k:` twice under session
  std::string octo_world;     ///< a 3-D world naming the FIFO as its octomap
  std::string bad_variant;    ///< an experiment whose variant is named ../../x
  std::string experiment;     ///< a valid experiment (for the full-device run)
  std::string lexicon;        ///< a store with one definition (for export)
  std::string alias_bomb;     ///< a 395-byte config whose aliases expand to 387 million nodes
  std::string many_params;    ///< a config giving the planner 40,000 params
  std::string many_overlay;   ///< a config extending many_params with 40,000 params of its own
  std::string other_base;     ///< a config giving the planner 20,000 params (p0..p19999)
  std::string other_overlay;  ///< a config extending other_base with 20,000 others (p20000..)
  std::string big_config;     ///< a config file of 1 MiB + 1 byte
};

/// A request line sent to one running `flipper session` (after its setup lines, each answered
/// ok); the answer must be ok:false with `code` and a message containing `message`, and the
/// session must go on answering.
struct SessionRow {
  const char* input;  ///< the cell of docs/bad-input.md's table
  const char* code;
  const char* message;  ///< an excerpt of the answer's error message
  std::function<std::vector<std::string>(const Scratch&)> setup;
  std::function<std::string(const Scratch&)> line;
  bool default_limits = false;  ///< sent to a session with the default config instead
};

/// A command line (arguments after `flipper`, run through bash); it must exit with `status`,
/// print "[code]" and `message`, and never die of a signal.
struct CliRow {
  const char* input;
  const char* code;
  const char* message;
  int status;
  std::function<std::string(const Scratch&)> command;
};

/// Settings of the session the SessionRows run in (small limits keep the rows fast; rows with
/// `default_limits` go to a session with the embedded default config and an in-memory store).
std::vector<std::string> session_settings();
const std::vector<SessionRow>& session_rows();
const std::vector<CliRow>& cli_rows();

/// The table of docs/bad-input.md (Markdown) rendered from the rows.
std::string render_table();

}  // namespace flipper::limitstest

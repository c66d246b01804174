// flipper run [--config F] [--set k=v] [--world W] [--user U] [--json] PROGRAM
// Runs one program on the default world (or W): canonical text is read directly; anything else
// goes through a session's parser — with the lexicon's rules visible to U (lexicon.sharing) —
// and the top candidate is taken, saying so when there were several. Prints the interpretation,
// the trace, the warnings and the final world (or one JSON object with --json). A sentence nothing
// parsed, and a program that cannot be done in this world, get their repair (docs/usage.md "run",
// docs/protocol.md "Repairs"): the repl's lines, or the protocol's "repair" member with --json.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/kernel/executor.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/naturalization/repair_extension.hpp"
#include "flipper/repl/outcome_json.hpp"
#include "flipper/repl/repl.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/svg/svg.hpp"
#include "flipper/wiring/session_factory.hpp"

namespace flipper::cli {
namespace {

struct RunOptions {
  CommonOptions common;
  std::string world_file;
  std::string user;
  std::string svg_file;
  bool json = false;
  std::string program;
};

struct Reading {
  sdk::Program program;
  std::size_t readings = 1;    ///< how many the parser found (1 for canonical text)
  double prob = 1.0;           ///< the chosen one's share
  std::string not_understood;  ///< why nothing parsed ("": understood)
  std::shared_ptr<const naturalization::Repair> repair;  ///< how to repair that (may be null)
};

// Canonical text first (deterministic); otherwise the session parser's best candidate, which
// sees the user's lexicon (the session answers exactly as the repl would).
Reading interpret(kernel::Session& session, const std::string& text) {
  session.check_length(text);  // as a query counts it (code points), also for canonical text
  try {
    Reading canonical;
    canonical.program = sdk::read_canonical(text);
    return canonical;
  } catch (const sdk::Error&) {
  }
  kernel::QueryRequest request;
  request.text = text;
  request.k = 1;
  const kernel::QueryResult result = session.query(request);  // the session's checks and codes
  if (result.query->shown.empty()) {
    Reading failed;
    // A failure says how to repair it (docs/protocol.md "Repairs").
    failed.repair = naturalization::repair_query(session, result);
    const std::string note = repl::unknown_words_note(session, text);
    failed.not_understood =
        "cannot understand '" + text +
        "': it is neither canonical text nor core language, nor a phrase of the lexicon visible "
        "to this user" +
        (note.empty() ? "" : ". " + note.substr(0, note.size() - 1)) +
        (failed.repair ? repl::repair_summary(*failed.repair) : "") +
        " (teach a phrase in `flipper repl`)";
    return failed;
  }
  const kernel::LastQuery& q = *result.query;
  const kernel::ShownCandidate& top = q.shown.front();
  Reading parsed;
  parsed.program = q.parse.candidates[top.index].program;
  parsed.readings = result.total();
  parsed.prob = q.probs[top.index];
  return parsed;
}

// A failure with its repair (docs/usage.md "run"): with --json one object, the protocol's
// "repair" member next to "error"; otherwise the error line and the repair's lines on stderr.
int fail_with_repair(const std::string& code, const std::string& message, int exit_code,
                     const nlohmann::json& repair, const std::string& lines) {
  const nlohmann::json more{{"repair", repair}};
  report_error("run", code, message, exit_code, sdk::StopCause::none, more);
  if (!json_output()) std::cerr << lines << std::flush;
  return exit_code;
}

// Why the program cannot be done in this world, and its nearest realizable variant
// (docs/naturalization.md §7), when the world decides it (naturalization::decided_by_world).
std::optional<naturalization::Unrealizable> explain(kernel::Session& session,
                                                    const sdk::Program& program,
                                                    const sdk::WorldState& world,
                                                    const sdk::Outcome& o) {
  if (!naturalization::decided_by_world(o)) return std::nullopt;
  return naturalization::explain_unrealizable(
      program, world, o, [&session](const sdk::Program& p, const sdk::WorldState& w) {
        return session.executor().run(p, w);  // the session's limits, as the run itself
      });
}

const char* act_name(sdk::TraceStep::Act a) {
  return a == sdk::TraceStep::Act::move ? "move" : a == sdk::TraceStep::Act::pick ? "pick" : "drop";
}

// A world's metric frame, when its object has one (`frame`: resolution and the metres of the
// grid's lower-left corner; the ros_map plugin writes it, docs/ros-maps.md "Metres out").
struct MetreFrame {
  double resolution = 1;
  double origin_x = 0;
  double origin_y = 0;
};

std::optional<MetreFrame> metre_frame(const kernel::Json& world) {
  const auto f = world.find("frame");
  if (f == world.end() || !f->is_object()) return std::nullopt;
  const auto r = f->find("resolution");
  const auto o = f->find("origin");
  if (r == f->end() || !r->is_number() || o == f->end() || !o->is_array() || o->size() < 2 ||
      !(*o)[0].is_number() || !(*o)[1].is_number())
    return std::nullopt;
  return MetreFrame{r->get<double>(), (*o)[0].get<double>(), (*o)[1].get<double>()};
}

// " (x m, y m)": the cell's centre in the frame, or nothing without a frame.
std::string in_metres(const sdk::Cell& c, const std::optional<MetreFrame>& f) {
  if (!f) return "";
  std::ostringstream s;
  s << " (" << f->origin_x + (c.x + 0.5) * f->resolution << " m, "
    << f->origin_y + (c.y + 0.5) * f->resolution << " m)";
  return s.str();
}

void print_human(const sdk::Program& program, const sdk::Outcome& o, int dims,
                 const std::optional<MetreFrame>& frame) {
  std::cout << "interpretation: " << sdk::render(program) << "\n";
  std::cout << "trace (" << o.trace.size() << " steps):\n";
  for (const auto& s : o.trace) {
    std::cout << "  " << act_name(s.act) << " " << sdk::to_string(s.cell, dims);
    if (s.act != sdk::TraceStep::Act::move)
      std::cout << " " << s.item.color << " " << s.item.shape << " (id " << s.item.id << ")";
    std::cout << "\n";
  }
  for (const auto& w : repl::collapse_warnings(repl::strings_json(o.warnings)))
    std::cout << "warning: " << w << "\n";
  std::cout << "realizable: " << (o.realizable ? "yes" : "no") << "\n";
  const sdk::WorldState& w = o.world;
  std::cout << "robot: " << sdk::to_string(w.robot, dims) << in_metres(w.robot, frame)
            << ", holding " << w.held.size() << (w.held.empty() ? "" : ":");
  for (const auto& h : w.held) std::cout << " " << h.color << " " << h.shape;
  std::cout << "\nitems (" << w.items.size() << "):";
  for (const auto& li : w.items)
    std::cout << " " << li.item.color << " " << li.item.shape << "@" << sdk::to_string(li.at, dims)
              << in_metres(li.at, frame);
  std::cout << "\n";
}

int run(const RunOptions& opts) {
  // With --json every failure is one JSON object on stdout (report_error, json_output()).
  auto fail = [](const std::string& code, const std::string& message, int exit_code,
                 sdk::StopCause stopped = sdk::StopCause::none) {
    return report_error("run", code, message, exit_code, stopped);
  };
  std::unique_ptr<kernel::Session> session;
  try {
    session = wiring::open_session(config_file(opts.common), opts.common.overrides);
  } catch (const sdk::Error& e) {
    return fail(e.code(), e.what(), kExitUsage);
  }
  kernel::Runtime& rt = session->runtime();
  if (!opts.user.empty()) session->set_user(opts.user);
  const int dims = rt.world.call("dims", [](const sdk::World& w) { return w.dims(); });
  sdk::WorldState world;
  try {
    world =
        opts.world_file.empty() ? rt.default_world : kernel::load_world_file(rt, opts.world_file);
  } catch (const sdk::Error& e) {
    return fail(e.code(), e.what(), kExitUsage);
  }
  session->set_world(world);
  Reading reading;
  try {
    reading = interpret(*session, opts.program);
  } catch (const sdk::Error& e) {
    return fail(e.code(), e.what(), kExitFailed, sdk::stop_cause_of(e));
  }
  if (!reading.not_understood.empty()) {
    if (!reading.repair) return fail(sdk::codes::kBadProgram, reading.not_understood, kExitFailed);
    return fail_with_repair(
        sdk::codes::kBadProgram, reading.not_understood, kExitFailed,
        naturalization::repair_json(*reading.repair),
        repl::repair_lines(*reading.repair,
                           "Teach it in `flipper repl`: `:define`, then the steps:"));
  }
  const sdk::Program& program = reading.program;
  if (reading.readings > 1 && !opts.json)
    std::fprintf(stderr,
                 "flipper run: note: took the top of %zu readings (p=%.2f); `flipper repl` shows "
                 "them all and lets you choose\n",
                 reading.readings, reading.prob);
  const sdk::Outcome o = session->executor().run(program, world);  // the session's limits
  std::optional<naturalization::Unrealizable> why;
  try {
    why = explain(*session, program, world, o);
  } catch (const sdk::Error& e) {
    return fail(e.code(), e.what(), kExitFailed, sdk::stop_cause_of(e));
  }
  const auto repair_member = [&] { return naturalization::unrealizable_json({{0, *why}}, dims); };
  if (o.error) {
    const std::string code = o.error_code.value_or(sdk::codes::kExecution);
    if (!why) return fail(code, *o.error, kExitFailed, o.stopped);
    return fail_with_repair(code, *o.error, kExitFailed, repair_member(),
                            repl::unrealizable_line(*why, dims) + "\n");
  }
  if (!opts.svg_file.empty()) {
    const kernel::Json before = session->world_json(world);
    const repl::Json trace = repl::trace_json(o.trace, dims);
    std::ofstream f(opts.svg_file);
    f << svg::world_picture(before, &trace, sdk::render(program));
    f.flush();
    if (!f) return fail("io", "cannot write '" + opts.svg_file + "'", kExitFailed);
  }
  if (opts.json) {
    nlohmann::json j = repl::outcome_json(o, dims);
    j["ok"] = true;
    j["formula"] = sdk::render(program);
    j["world"] = session->world_json(o.world);
    j["readings"] = reading.readings;
    if (why) j["repair"] = repair_member();
    std::cout << j.dump() << "\n";
  } else {
    print_human(program, o, dims, metre_frame(session->world_json(o.world)));
    if (why) std::cout << repl::unrealizable_line(*why, dims) << "\n";
  }
  return kExitOk;
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("run", "Run one program (canonical text or core language) on a world");
  static RunOptions opts;
  add_common_options(*cmd, opts.common);
  cmd->add_option("--world", opts.world_file, "World file (default: the config's world.file)");
  cmd->add_option("--user", opts.user,
                  "Whose lexicon view to parse with (lexicon.sharing decides what is visible)");
  cmd->add_flag("--json", opts.json, "Print one JSON object (protocol shapes)");
  cmd->add_option("--svg", opts.svg_file, "Also draw the world and the plan into this SVG file");
  cmd->add_option("program", opts.program, "The program, e.g. 'visit world containing item is red'")
      ->required();
  cmd->callback([] { std::exit(run(opts)); });
}

}  // namespace flipper::cli

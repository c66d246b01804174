// flipper session [--config F] [--set k=v] [SCRIPT|-]: session-protocol requests, one JSON line in,
// one JSON answer line out, flushed after each so another program can drive it interactively.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "common.hpp"
#include "dds_services.hpp"
#include "flipper/kernel/line_reader.hpp"
#include "flipper/wiring/session_factory.hpp"

namespace flipper::cli {
namespace {

int run_session(const CommonOptions& opts, const std::string& script) {
  std::ifstream file;
  std::istream* in = &std::cin;
  if (!script.empty() && script != "-") {
    file.open(script);
    if (!file) {
      return report_error("session", "bad_request", "cannot read script '" + script + "'",
                          kExitUsage);
    }
    in = &file;
  }
  kernel::SessionHost host = kernel::open_host(config_file(opts), opts.overrides);
  const DdsServices dds = DdsServices::start(host);  // publish.plans, lexicon.replication
  auto session = dds.open(host);
  const std::uint64_t max_bytes = session->options().input.max_line_bytes;
  std::string line;
  std::uint64_t bytes = 0;
  for (;;) {
    const kernel::LineRead read = kernel::read_request_line(*in, max_bytes, line, bytes);
    if (read == kernel::LineRead::eof) break;
    std::string answer = read == kernel::LineRead::too_long ? session->line_too_long(bytes)
                                                            : session->handle_line(line);
    if (answer.empty()) continue;
    answer.push_back('\n');
    std::fwrite(answer.data(), 1, answer.size(), stdout);
    std::fflush(stdout);
  }
  return kExitOk;
}

}  // namespace

void add_session_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "session", "Answer session-protocol requests (JSON lines) from SCRIPT or standard input");
  static CommonOptions opts;
  static std::string script;
  add_common_options(*cmd, opts);
  cmd->add_option("script", script, "Script of JSON lines ('-' or omitted: standard input)");
  on_run(*cmd, [] {
    std::ios::sync_with_stdio(false);
    return run_session(opts, script);
  });
}
}  // namespace flipper::cli

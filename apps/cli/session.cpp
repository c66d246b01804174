// flipper session [--config F] [--set k=v] [SCRIPT|-]: session-protocol requests, one JSON line in,
// one JSON answer line out, flushed after each so another program can drive it interactively.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "common.hpp"
#include "dds_services.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/wiring/session_factory.hpp"
#include "request_lines.hpp"
#include "sanitizer_build.hpp"

namespace flipper::cli {
namespace {

constexpr bool kSanitized = kAddressSanitizer || kThreadSanitizer;

/// The process is about to exit: the lexicon store is closed properly (checkpoint, WAL removed),
/// but the runtime and its rules are not freed one by one (at 10k rules their teardown is ~10%
/// of a short session's CPU; docs/naturalization.md §5 "Start-up at scale"). They stay reachable
/// from a static, so leak checkers see no leak; sanitizer builds still tear everything down.
void keep_until_exit(wiring::SessionHost host) {
  if (host.naturalizer) host.naturalizer->close_store();
  if constexpr (kSanitized) return;  // destroyed here, checked by the sanitizer
  // volatile: the store below is not optimised away (the pointer is never read).
  [[maybe_unused]] static wiring::SessionHost* volatile kept = nullptr;
  kept = new wiring::SessionHost(std::move(host));
}

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
  wiring::SessionHost host = wiring::open_host(config_file(opts), opts.overrides);
  {
    const DdsServices dds = DdsServices::start(host);  // publish.plans, lexicon.replication
    auto session = dds.open(host);
    const std::uint64_t max_bytes = session->options().input.max_line_bytes;
    std::string line;
    std::uint64_t bytes = 0;
    for (;;) {
      const LineRead read = read_request_line(*in, max_bytes, line, bytes);
      if (read == LineRead::eof) break;
      std::string answer =
          read == LineRead::too_long ? session->line_too_long(bytes) : session->handle_line(line);
      if (answer.empty()) continue;
      answer.push_back('\n');
      std::fwrite(answer.data(), 1, answer.size(), stdout);
      std::fflush(stdout);
    }
  }  // the session, then the DDS services (their threads), end here
  keep_until_exit(std::move(host));
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

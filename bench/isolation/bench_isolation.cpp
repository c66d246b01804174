// The cost of plugins.isolation: process (docs/plugins-untrusted.md §6), each figure next to its
// target:
//   latency  `flipper session` answering the same mix of study-map queries (the queries of
//            bench_studio: visits, loops over rooms and points, an error) with in_process and
//            with process isolation, alternating blocks of queries between the two sessions so
//            that both see the same machine load: per-query p50 and p99 of each, and the
//            difference of the two per-query medians; then the same mix with k = 0 (the
//            query is parsed, no candidate executed: no plan call), which is the cost of the
//            parse's own child process; then accepts: each query of the mix answered, then
//            its first reading accepted, the accept's round trip timed (it applies the execution
//            its query showed, planning nothing again, and runs the scorer's learn, in a child
//            with process isolation: the learnt weights cross as values)
//   memory   the sessions' resident memory (VmRSS, VmHWM) after the queries: isolation must not
//            grow the long-lived process; and one plan call's process (a planner that plans, then
//            spins: tests/support/evil_planner mode hang) while it runs: its private dirty
//            memory and page tables (what a fork costs beyond the pages it shares)
// Usage: bench_isolation --flipper BIN [--queries 800]
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_common.hpp"
#include "child_process.hpp"
#include "process_children.hpp"

namespace {

using flipper::bench::kStudyQueries;
using flipper::bench::percentile;

using Clock = std::chrono::steady_clock;
using flipper::testsupport::ChildProcess;
using flipper::testsupport::children_of;

// A /proc/PID/<file> field in kB ("VmRSS:  1234 kB"), 0 when absent.
long proc_kb(int pid, const std::string& file, const std::string& field) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/" + file);
  for (std::string line; std::getline(f, line);)
    if (line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  return 0;
}

std::unique_ptr<ChildProcess> session(const std::string& flipper, const std::string& isolation,
                                      const std::vector<std::string>& more = {}) {
  std::vector<std::string> args{
      flipper, "session",          "--set", "lexicon.path=:memory:",
      "--set", "lexicon.preload=", "--set", "plugins.isolation=" + isolation};
  for (const auto& m : more) {
    args.push_back("--set");
    args.push_back(m);
  }
  return std::make_unique<ChildProcess>(args);
}

// One query and its answer line; the round trip in ms (negative: no answer).
double ask(ChildProcess& s, const std::string& text, int k = -1) {
  nlohmann::json request{{"op", "query"}, {"text", text}};
  if (k >= 0) request["k"] = k;
  const std::string line = request.dump();
  const auto t0 = Clock::now();
  if (!s.write_line(line)) return -1;
  const std::string answer = s.read_line(std::chrono::seconds(60));
  if (answer.rfind("{\"ok\":", 0) != 0) return -1;
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Accepts the last query's reading 0: the round trip in ms, or negative when it was not
// accepted (no reading, or its execution failed: the same in both sessions).
double accept(ChildProcess& s) {
  const auto t0 = Clock::now();
  if (!s.write_line(R"({"op":"accept","rank":0})")) return -1;
  const std::string answer = s.read_line(std::chrono::seconds(60));
  if (answer.rfind(R"({"ok":true,"op":"accept")", 0) != 0) return -1;
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::string flipper;
  int queries = 800;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--flipper")
      flipper = v;
    else if (k == "--queries")
      queries = std::stoi(v);
    else {
      std::cerr << "bench_isolation: unknown option " << k << "\n";
      return 2;
    }
  }
  if (flipper.empty()) {
    std::cerr << "usage: bench_isolation --flipper BIN [--queries N]\n";
    return 2;
  }
  auto in_process = session(flipper, "in_process");
  auto process = session(flipper, "process");
  std::vector<double> ms_in, ms_proc, diff;
  std::vector<std::vector<double>> by_query_in(kStudyQueries.size()),
      by_query_proc(kStudyQueries.size());
  int errors = 0;
  const auto n = static_cast<int>(kStudyQueries.size());
  for (int i = 0; i < n; ++i) {  // warm-up: the first answers load what later ones reuse
    errors += ask(*in_process, kStudyQueries[static_cast<std::size_t>(i)]) < 0;
    errors += ask(*process, kStudyQueries[static_cast<std::size_t>(i)]) < 0;
  }
  for (int i = 0; i < queries; ++i) {
    const std::string& q = kStudyQueries[static_cast<std::size_t>(i % n)];
    // Alternate which goes first, so neither always follows the other.
    const bool first_in = i % 2 == 0;
    const double a = first_in ? ask(*in_process, q) : ask(*process, q);
    const double b = first_in ? ask(*process, q) : ask(*in_process, q);
    const double t_in = first_in ? a : b, t_proc = first_in ? b : a;
    if (t_in < 0 || t_proc < 0) {
      ++errors;
      continue;
    }
    ms_in.push_back(t_in);
    ms_proc.push_back(t_proc);
    diff.push_back(t_proc - t_in);
    by_query_in[static_cast<std::size_t>(i % n)].push_back(t_in);
    by_query_proc[static_cast<std::size_t>(i % n)].push_back(t_proc);
  }
  // Parse only (k = 0): one child process per query with process isolation, for the parse.
  std::vector<double> parse_in, parse_proc;
  for (int i = 0; i < queries; ++i) {
    const std::string& q = kStudyQueries[static_cast<std::size_t>(i % n)];
    const bool first_in = i % 2 == 0;
    const double a = first_in ? ask(*in_process, q, 0) : ask(*process, q, 0);
    const double b = first_in ? ask(*process, q, 0) : ask(*in_process, q, 0);
    if (a < 0 || b < 0) {
      ++errors;
      continue;
    }
    parse_in.push_back(first_in ? a : b);
    parse_proc.push_back(first_in ? b : a);
  }
  // Accepts: both sessions learn the same, so both keep answering the same.
  std::vector<double> accept_in, accept_proc;
  int accept_refused = 0;
  for (int i = 0; i < queries; ++i) {
    const std::string& q = kStudyQueries[static_cast<std::size_t>(i % n)];
    if (ask(*in_process, q) < 0 || ask(*process, q) < 0) {
      ++errors;
      continue;
    }
    const bool first_in = i % 2 == 0;
    const double a = first_in ? accept(*in_process) : accept(*process);
    const double b = first_in ? accept(*process) : accept(*in_process);
    if ((a < 0) != (b < 0)) ++errors;  // one session accepted, the other did not
    if (a < 0 || b < 0) {
      ++accept_refused;
      continue;
    }
    accept_in.push_back(first_in ? a : b);
    accept_proc.push_back(first_in ? b : a);
  }
  const long rss_in = proc_kb(in_process->pid(), "status", "VmRSS");
  const long rss_proc = proc_kb(process->pid(), "status", "VmRSS");
  const long hwm_in = proc_kb(in_process->pid(), "status", "VmHWM");
  const long hwm_proc = proc_kb(process->pid(), "status", "VmHWM");

  // One plan call's process while it runs: the evil planner plans (breadth-first on the study
  // map), then spins; its memory is read, then it is killed (the answer: plugin_crashed).
  const std::string evil = std::string(FLIPPER_BINARY_DIR) + "/tests/plugins/evil";
  auto spinning = session(
      flipper, "process",
      {"plugin_paths=[" + evil + "]", "planner.plugin=evil_planner", "planner.params.mode=hang"});
  spinning->write_line(R"({"op":"query","text":"visit room1"})");
  std::vector<int> kids;
  const auto until = Clock::now() + std::chrono::seconds(60);
  while ((kids = children_of(spinning->pid())).empty() && Clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  long child_rss = 0, child_private = 0, child_pte = 0, parent_rss = 0;
  // The query's parse has a child of its own first (a few ms): the one still there after
  // 100 ms is the plan's, past the planning, spinning.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  kids = children_of(spinning->pid());
  if (kids.size() == 1) {
    child_rss = proc_kb(kids[0], "smaps_rollup", "Rss");
    child_private = proc_kb(kids[0], "smaps_rollup", "Private_Dirty");
    child_pte = proc_kb(kids[0], "status", "VmPTE");
    parent_rss = proc_kb(spinning->pid(), "status", "VmRSS");
    ::kill(kids[0], SIGKILL);
  } else {
    ++errors;
  }
  const std::string crashed = spinning->read_line(std::chrono::seconds(60));
  if (crashed.find("plugin_crashed") == std::string::npos) ++errors;

  const double p50_in = percentile(ms_in, 0.5), p99_in = percentile(ms_in, 0.99);
  const double p50_proc = percentile(ms_proc, 0.5), p99_proc = percentile(ms_proc, 0.99);
  const double p50_diff = percentile(diff, 0.5);
  std::printf("%d queries x 2 sessions (study map, the bench_studio mix), %d errors (target 0)\n",
              queries, errors);
  std::printf("in_process  per query p50 %.3f ms, p99 %.3f ms\n", p50_in, p99_in);
  std::printf("process     per query p50 %.3f ms, p99 %.3f ms\n", p50_proc, p99_proc);
  std::printf(
      "overhead    p50 %+.3f ms (target <= 2 ms), p99 %+.3f ms (target <= 25 ms); "
      "median of per-query differences %+.3f ms\n",
      p50_proc - p50_in, p99_proc - p99_in, p50_diff);
  const double parse_p50_in = percentile(parse_in, 0.5), parse_p99_in = percentile(parse_in, 0.99);
  const double parse_p50 = percentile(parse_proc, 0.5), parse_p99 = percentile(parse_proc, 0.99);
  std::printf(
      "parse only (k = 0): in_process p50 %.3f ms, p99 %.3f ms; process p50 %.3f ms, p99 %.3f "
      "ms; overhead p50 %+.3f ms (target <= 2 ms), p99 %+.3f ms (target <= 25 ms)\n",
      parse_p50_in, parse_p99_in, parse_p50, parse_p99, parse_p50 - parse_p50_in,
      parse_p99 - parse_p99_in);
  const double acc_p50_in = percentile(accept_in, 0.5), acc_p99_in = percentile(accept_in, 0.99);
  const double acc_p50 = percentile(accept_proc, 0.5), acc_p99 = percentile(accept_proc, 0.99);
  std::printf(
      "accept (%zu accepted, %d not acceptable in both): in_process p50 %.3f ms, p99 %.3f ms; "
      "process p50 %.3f ms, p99 %.3f ms; overhead p50 %+.3f ms (target <= 2 ms), p99 %+.3f ms "
      "(target <= 25 ms)\n",
      accept_in.size(), accept_refused, acc_p50_in, acc_p99_in, acc_p50, acc_p99,
      acc_p50 - acc_p50_in, acc_p99 - acc_p99_in);
  std::printf("per utterance, median in_process / process (ms):\n");
  for (std::size_t q = 0; q < kStudyQueries.size(); ++q)
    std::printf("  %7.3f / %7.3f  %s\n", percentile(by_query_in[q], 0.5),
                percentile(by_query_proc[q], 0.5), kStudyQueries[q].c_str());
  std::printf(
      "session RSS in_process %ld kB (peak %ld kB), process %ld kB (peak %ld kB): "
      "%+ld kB (target <= 1024 kB)\n",
      rss_in, hwm_in, rss_proc, hwm_proc, rss_proc - rss_in);
  std::printf(
      "one plan call's process: RSS %ld kB (shared with the session's %ld kB), private "
      "dirty %ld kB + page tables %ld kB (target <= 8192 kB)\n",
      child_rss, parent_rss, child_private, child_pte);
  const bool ok = errors == 0 && p50_proc - p50_in <= 2.0 && p99_proc - p99_in <= 25.0 &&
                  parse_p50 - parse_p50_in <= 2.0 && parse_p99 - parse_p99_in <= 25.0 &&
                  acc_p50 - acc_p50_in <= 2.0 && acc_p99 - acc_p99_in <= 25.0 &&
                  rss_proc - rss_in <= 1024 && child_private + child_pte <= 8192;
  return ok ? 0 : 1;
}

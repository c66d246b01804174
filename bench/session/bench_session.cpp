// Session latency, start-up and memory (h5 brief §5):
// - per-query latency of the `query` op (parse + plan the shown candidates, and a variant planning
//   every candidate) over every dev-corpus `q` utterance on the study map, p50/p99, next to the
//   original server's logged walltime_s for the same queries;
// - start-up of `flipper session` to its first answer (spawned, median of runs);
// - peak resident memory (VmHWM) of a `flipper session` process that answered every query.
// Usage: bench_session [--corpus FILE] [--flipper BIN] [--runs N] [--latency-only 1]
//                      [--slowest N]   (lists the N queries with the most CPU time, k shown)
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/wiring/session_factory.hpp"

using flipper::kernel::Json;
using Clock = std::chrono::steady_clock;

#include "bench_common.hpp"

namespace {

using flipper::bench::percentile;

struct Query {
  std::string text;
  double original_s = -1;
};

std::vector<Query> load_queries(const std::string& path) {
  std::vector<Query> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    auto r = nlohmann::json::parse(line);
    if (r.value("kind", "") != "q" || !r["utterance"].is_string()) continue;
    Query q;
    q.text = r["utterance"].get<std::string>();
    if (r.contains("walltime_s") && r["walltime_s"].is_number()) q.original_s = r["walltime_s"];
    out.push_back(std::move(q));
  }
  return out;
}

// Thread CPU time: on a shared machine wall time also measures the other processes.
double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) / 1e6;
}

// A child `flipper session` with pipes.
struct Child {
  pid_t pid = -1;
  int to = -1, from = -1;
  std::string buf;
  explicit Child(const std::string& bin) {
    int in[2], out[2];
    if (pipe(in) != 0 || pipe(out) != 0) throw std::runtime_error("pipe");
    pid = fork();
    if (pid == 0) {
      dup2(in[0], 0);
      dup2(out[1], 1);
      close(in[1]);
      close(out[0]);
      execl(bin.c_str(), bin.c_str(), "session", "--set",
            "lexicon.path=/tmp/flipper-bench-session.sqlite", static_cast<char*>(nullptr));
      _exit(127);
    }
    close(in[0]);
    close(out[1]);
    to = in[1];
    from = out[0];
  }
  void send(const std::string& line) {
    std::string l = line + "\n";
    for (std::size_t done = 0; done < l.size();) {
      ssize_t n = write(to, l.data() + done, l.size() - done);
      if (n <= 0) throw std::runtime_error("write to flipper session failed");
      done += static_cast<std::size_t>(n);
    }
  }
  std::string receive() {
    for (;;) {
      if (auto nl = buf.find('\n'); nl != std::string::npos) {
        std::string line = buf.substr(0, nl);
        buf.erase(0, nl + 1);
        return line;
      }
      pollfd p{from, POLLIN, 0};
      if (poll(&p, 1, 60000) <= 0) return {};
      char chunk[65536];
      ssize_t n = read(from, chunk, sizeof chunk);
      if (n <= 0) return {};
      buf.append(chunk, static_cast<std::size_t>(n));
    }
  }
  long vm_hwm_kb() const {
    std::ifstream st("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(st, line);)
      if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
    return -1;
  }
  ~Child() {
    close(to);
    close(from);
    int status;
    waitpid(pid, &status, 0);
  }
};

std::string query_line(const std::string& text, int k) {
  return Json{{"op", "query"}, {"text", text}, {"k", k}}.dump();
}

}  // namespace

int main(int argc, char** argv) {
  std::string corpus = std::string(FLIPPER_STUDY_DIR) + "/dev/queries.jsonl";
  std::string flipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";
  int runs = 10;
  bool latency_only = false;
  std::size_t slowest = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string a = argv[i];
    if (a == "--corpus") corpus = argv[i + 1];
    if (a == "--flipper") flipper = argv[i + 1];
    if (a == "--runs") runs = std::stoi(argv[i + 1]);
    if (a == "--latency-only") latency_only = std::string(argv[i + 1]) != "0";
    if (a == "--slowest") slowest = std::stoul(argv[i + 1]);
  }
  const auto queries = load_queries(corpus);
  std::printf("queries: %zu dev-corpus q utterances (%s)\n", queries.size(), corpus.c_str());

  // In-process latency: a fresh session on the default (study) world; nothing is accepted, so
  // every query runs on the study map.
  auto session = flipper::wiring::open_session(std::nullopt,
                                               {"lexicon.path=/tmp/flipper-bench-session.sqlite"});
  const int k = session->options().k;
  std::vector<double> shown_ms, all_ms, original_ms, shown_cpu_ms;
  std::size_t errors = 0;
  for (const auto& q : queries) {
    if (q.original_s >= 0) original_ms.push_back(q.original_s * 1000.0);
    for (int variant = 0; variant < 2; ++variant) {
      std::string line = query_line(q.text, variant == 0 ? k : 1000000);
      const double c0 = cpu_ms();
      auto t0 = Clock::now();
      std::string answer = session->handle_line(line);
      double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      (variant == 0 ? shown_ms : all_ms).push_back(ms);
      if (variant == 0) shown_cpu_ms.push_back(cpu_ms() - c0);
      if (variant == 0 && answer.find("\"ok\":true") == std::string::npos) ++errors;
    }
  }
  // The parser alone (same requests), to separate parsing from planning and answer building.
  std::vector<double> parse_ms;
  {
    auto& rt = session->runtime();
    for (const auto& q : queries) {
      flipper::sdk::ParseRequest pr;
      pr.tokens = flipper::sdk::tokenize(q.text);
      pr.context.tokens = &pr.tokens;
      pr.context.user = session->user();
      pr.context.usage = rt.usage.get();
      pr.scorer = rt.scorer.borrow();
      auto t0 = Clock::now();
      auto result = rt.parser.borrow()->parse(pr);
      parse_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
  }
  const double o50 = percentile(original_ms, 0.5), o99 = percentile(original_ms, 0.99);
  auto row = [&](const char* name, const std::vector<double>& v) {
    double p50 = percentile(v, 0.5), p99 = percentile(v, 0.99);
    std::printf(
        "%-34s p50 %8.3f ms  p99 %8.3f ms  max %8.3f ms   speed-up vs original p50 %6.1fx p99 "
        "%6.1fx\n",
        name, p50, p99, percentile(v, 1.0), o50 / p50, o99 / p99);
  };
  std::printf("%-34s p50 %8.3f ms  p99 %8.3f ms  (logged walltime_s, parse only)\n",
              "original server", o50, o99);
  row(("query op, k=" + std::to_string(k) + " (parse+plan shown)").c_str(), shown_ms);
  row("query op, every candidate planned", all_ms);
  row("parser plugin alone", parse_ms);
  row("query op, k shown, thread CPU time", shown_cpu_ms);
  std::printf("answers with ok=false: %zu\n", errors);
  if (slowest > 0) {
    std::vector<std::size_t> order(queries.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return shown_cpu_ms[a] > shown_cpu_ms[b]; });
    for (std::size_t i = 0; i < std::min(slowest, order.size()); ++i)
      std::printf("slow %8.3f ms cpu  %s\n", shown_cpu_ms[order[i]],
                  Json(queries[order[i]].text).dump().c_str());
  }
  if (latency_only) return 0;

  // Start-up to first answer, spawned.
  std::vector<double> startup;
  for (int r = 0; r < runs; ++r) {
    auto t0 = Clock::now();
    Child c(flipper);
    c.send(R"({"op":"state"})");
    std::string a = c.receive();
    startup.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (a.find("\"ok\":true") == std::string::npos) {
      std::fprintf(stderr, "flipper session did not answer: %s\n", a.c_str());
      return 1;
    }
  }
  std::printf(
      "start-up to first answer (flipper session, %d runs): median %.1f ms, max %.1f ms (target <= "
      "50 ms)\n",
      runs, percentile(startup, 0.5), percentile(startup, 1.0));

  // Peak memory of a flipper session that answered the whole corpus.
  {
    Child c(flipper);
    for (const auto& q : queries) {
      c.send(query_line(q.text, k));
      if (c.receive().empty()) {
        std::fprintf(stderr, "flipper session stopped answering\n");
        return 1;
      }
    }
    long kb = c.vm_hwm_kb();
    std::printf(
        "peak resident memory (VmHWM) of flipper session after %zu queries: %.1f MB (target <= 25 "
        "MB)\n",
        queries.size(), static_cast<double>(kb) / 1024.0);
  }
  return 0;
}

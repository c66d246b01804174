// Load benchmark of `flipper serve` on loopback: U concurrent users (threads, each its own
// keep-alive connection and session) send Q queries each on the study map, in two modes:
//   paced   each user sends a query every --interval-ms (users think between queries); the
//           target applies here: 0 errors, p99 round trip <= 5 ms
//   flood   each user sends the next query as soon as the answer is in (saturation: the
//           throughput of one kernel; latency is then queueing, reported without a target)
// Usage: bench_studio --flipper BIN [--users 100] [--queries 1000] [--interval-ms 50]
//                     [--mode paced|flood|both]
#include <httplib.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bench_common.hpp"
#include "child_process.hpp"

namespace {

using flipper::bench::kStudyQueries;
using flipper::bench::percentile;

using Clock = std::chrono::steady_clock;

struct Options {
  std::string flipper;
  int users = 100;
  int queries = 1000;
  int interval_ms = 50;
  std::string mode = "both";
};

struct Result {
  std::vector<double> ms;
  long errors = 0;
  double seconds = 0;
};

Result load(int port, const Options& o, bool paced) {
  std::vector<std::vector<double>> per_user(static_cast<std::size_t>(o.users));
  std::atomic<long> errors{0};
  std::atomic<int> ready{0};
  std::atomic<bool> go{false};
  std::vector<std::thread> users;
  for (int u = 0; u < o.users; ++u)
    users.emplace_back([&, u] {
      httplib::Client c("127.0.0.1", port);
      c.set_keep_alive(true);
      c.set_tcp_nodelay(true);  // else Nagle + delayed ACK add 40 ms to each request
      c.set_read_timeout(60);
      auto first = c.Post("/api/v1/request", R"({"op":"state"})", "application/json");
      const std::string path =
          first ? "/api/v1/request?session=" + first->get_header_value("Flipper-Session") : "";
      if (!first || first->status != 200) ++errors;
      ++ready;
      while (!go) std::this_thread::yield();
      auto& ms = per_user[static_cast<std::size_t>(u)];
      ms.reserve(static_cast<std::size_t>(o.queries));
      // Paced users start spread over one interval, like people who did not all press Enter
      // at the same instant.
      auto next = Clock::now() + std::chrono::microseconds(o.interval_ms * 1000 * u / o.users);
      for (int i = 0; i < o.queries; ++i) {
        if (paced) {
          std::this_thread::sleep_until(next);
          next += std::chrono::milliseconds(o.interval_ms);
        }
        const std::string& text =
            kStudyQueries[static_cast<std::size_t>(u + i) % kStudyQueries.size()];
        const std::string body = nlohmann::json{{"op", "query"}, {"text", text}}.dump();
        const auto t0 = Clock::now();
        auto res = c.Post(path.c_str(), body, "application/json");
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        if (!res || res->status != 200 || res->body.rfind("{\"ok\":true", 0) != 0) ++errors;
      }
    });
  while (ready < o.users) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const auto start = Clock::now();
  go = true;
  for (auto& t : users) t.join();
  Result r;
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  r.errors = errors;
  for (auto& v : per_user) r.ms.insert(r.ms.end(), v.begin(), v.end());
  return r;
}

void report(const char* name, Result r, const Options& o, bool target) {
  const double p50 = percentile(r.ms, 0.50), p99 = percentile(r.ms, 0.99);
  const double max = r.ms.empty() ? 0 : *std::max_element(r.ms.begin(), r.ms.end());
  std::printf("%-6s %d users x %d queries%s: %zu answers, %ld errors (target 0), %.0f queries/s\n",
              name, o.users, o.queries,
              target ? (" (one every " + std::to_string(o.interval_ms) + " ms each)").c_str() : "",
              r.ms.size(), r.errors, static_cast<double>(r.ms.size()) / r.seconds);
  std::printf("       round trip p50 %.2f ms, p99 %.2f ms%s, max %.2f ms\n", p50, p99,
              target ? " (target <= 5 ms)" : "", max);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--flipper")
      o.flipper = v;
    else if (k == "--users")
      o.users = std::stoi(v);
    else if (k == "--queries")
      o.queries = std::stoi(v);
    else if (k == "--interval-ms")
      o.interval_ms = std::stoi(v);
    else if (k == "--mode")
      o.mode = v;
    else {
      std::cerr << "bench_studio: unknown option " << k << "\n";
      return 2;
    }
  }
  if (o.flipper.empty()) {
    std::cerr << "usage: bench_studio --flipper BIN [--users N] [--queries N] [--interval-ms N] "
                 "[--mode paced|flood|both]\n";
    return 2;
  }
  char tmpl[] = "/tmp/flipper-bench-studio-XXXXXX";
  const std::string dir = ::mkdtemp(tmpl);
  flipper::testsupport::ChildProcess server(
      {o.flipper, "serve",
       "--set",   "serve.host=127.0.0.1",
       "--set",   "serve.port=0",
       "--set",   "lexicon.path=" + dir + "/lexicon.sqlite",
       "--set",   "lexicon.preload=",
       "--set",   "serve.threads=" + std::to_string(o.users + 16),
       "--set",   "serve.rate_per_second=1000000",
       "--set",   "serve.rate_burst=1000000",
       "--set",   "serve.sessions_per_address=100000",
       "--set",   "serve.new_sessions_per_minute=100000",
       "--set",   "serve.max_connections_per_address=100000"});
  const std::string line = server.read_line(std::chrono::seconds(30));
  const auto at = line.find("127.0.0.1:");
  if (at == std::string::npos) {
    std::cerr << "bench_studio: the server did not start: " << line << "\n";
    return 1;
  }
  const int port = std::stoi(line.substr(at + 10));
  int rc = 0;
  if (o.mode == "paced" || o.mode == "both") {
    Result r = load(port, o, true);
    rc |= r.errors != 0;
    report("paced", std::move(r), o, true);
  }
  if (o.mode == "flood" || o.mode == "both") {
    Result r = load(port, o, false);
    rc |= r.errors != 0;
    report("flood", std::move(r), o, false);
  }
  server.kill_now();
  std::filesystem::remove_all(dir);
  return rc;
}

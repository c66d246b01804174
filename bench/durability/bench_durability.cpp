// Accept and define latency of `flipper session` at lexicon.durability: full and normal
// (docs/naturalization.md §5 "Durability and latency"): the round trip of each request over the
// session's pipes (client clock), p50/p99 per level. The levels alternate round by round in one
// run, each round a fresh process and store file in a temporary folder, so that both see the same
// machine (absolute times on a shared machine vary from day to day; the ratio is the figure).
// Each define adds a new head; each accept follows a query of one of those heads.
// A second part (serve_part.cpp) runs `flipper serve` with a pool of kernels on one store and
// concurrent HTTP clients, at full with and without group commit (lexicon.group_commit,
// docs/naturalization.md §5 "Group commit") and at normal, alternating round by round, with the
// WAL syncs per write the server counted. Both parts are set next to the original: the 2018
// server's accept and define times are not recorded (data/study2018: only a query's walltime_s),
// so the ratio shown is its recorded `:q` server time (p50, p99 over the dev queries) over
// Flipper's accept/define round trip, a proxy stated as such (docs/benchmarks.md).
// Usage: bench_durability [--flipper BIN] [--rounds N] [--ops N] [--serve-rounds N]
//          [--clients N] [--kernels N] [--serve-ops N]   (stores in $TMPDIR or /tmp)
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "serve_part.hpp"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

namespace {

double pct(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

double since_ms(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

bool ok(const std::string& answer) {
  return answer.find("\"ok\":true") != std::string::npos;
}

struct Times {
  std::vector<double> accept_ms, define_ms;
};

// One round: a fresh `flipper session` on its own store at `level`, `ops` defines, then `ops`
// accepts. Throws on an answer that is not ok (a benchmark of refusals measures nothing).
void round(const std::string& flipper, const fs::path& store, const std::string& level, bool group,
           int ops, Times& into) {
  flipper::testsupport::ChildProcess c(
      {flipper, "session", "--set", "lexicon.path=" + store.string(), "--set",
       "lexicon.durability=" + level, "--set",
       std::string("lexicon.group_commit=") + (group ? "true" : "false")});
  auto ask = [&](const std::string& line) {
    if (!c.write_line(line)) throw std::runtime_error("flipper session stopped reading");
    std::string a = c.read_line(std::chrono::seconds(120));
    if (!ok(a)) throw std::runtime_error("not ok: " + line + " -> " + a.substr(0, 300));
    return a;
  };
  ask(R"({"op":"state"})");  // started, store open
  auto head = [](int i) { return "zq" + std::to_string(i) + " hop"; };
  for (int i = 0; i < ops; ++i) {
    const std::string line =
        json{{"op", "define"}, {"head", head(i)}, {"body", {"move left", "move right"}}}.dump();
    auto t0 = Clock::now();
    ask(line);
    into.define_ms.push_back(since_ms(t0));
  }
  // Each accept follows a query of a head defined above (an induced rule: its use counter and
  // the scorer's changed weights are written), on the study map.
  for (int i = 0; i < ops; ++i) {
    ask(R"({"op":"world","file":"configs/worlds/study2018.json"})");
    ask(json{{"op", "query"}, {"text", head(i)}}.dump());
    auto t0 = Clock::now();
    ask(R"({"op":"accept","rank":0})");
    into.accept_ms.push_back(since_ms(t0));
  }
  if (c.finish() != 0) throw std::runtime_error("flipper session did not exit 0");
}

/// The configurations measured: lexicon.durability and lexicon.group_commit.
struct Level {
  const char* name;
  const char* durability;
  bool group;
};
constexpr Level kLevels[] = {{"full, group commit", "full", true},
                             {"full, no group commit", "full", false},
                             {"normal", "normal", false}};

/// The original's recorded `:q` server times (ms): walltime_s of every query of the dev split.
std::vector<double> original_query_ms() {
  std::ifstream in(std::string(FLIPPER_STUDY_DIR) + "/dev/queries.jsonl");
  std::vector<double> ms;
  for (std::string line; std::getline(in, line);) {
    const json q = json::parse(line);
    if (q.value("kind", "") == "q" && q.contains("walltime_s"))
      ms.push_back(1000.0 * q["walltime_s"].get<double>());
  }
  return ms;
}

void print_times(const char* name, const std::vector<double>& accept,
                 const std::vector<double>& define, const std::string& extra) {
  std::printf("  %-22s accept p50 %7.3f  p99 %7.3f ms   define p50 %7.3f  p99 %7.3f ms%s\n", name,
              pct(accept, 0.5), pct(accept, 0.99), pct(define, 0.5), pct(define, 0.99),
              extra.c_str());
}

void print_ratios(const char* name, const std::vector<double>& accept,
                  const std::vector<double>& define, double orig_p50, double orig_p99) {
  std::printf("  %-22s accept %6.1fx p50 %6.1fx p99   define %6.1fx p50 %6.1fx p99\n", name,
              orig_p50 / pct(accept, 0.5), orig_p99 / pct(accept, 0.99),
              orig_p50 / pct(define, 0.5), orig_p99 / pct(define, 0.99));
}

}  // namespace

int main(int argc, char** argv) {
  namespace dur = flipper::bench::durability;
  std::string flipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";
  int rounds = 3, ops = 100, serve_rounds = 2;
  dur::ServeRound serve;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    const std::string v = argv[i + 1];
    if (a == "--flipper") {
      flipper = v;
    } else if (a == "--rounds") {
      rounds = std::stoi(v);
    } else if (a == "--ops") {
      ops = std::stoi(v);
    } else if (a == "--serve-rounds") {
      serve_rounds = std::stoi(v);
    } else if (a == "--clients") {
      serve.clients = std::stoi(v);
    } else if (a == "--kernels") {
      serve.kernels = std::stoi(v);
    } else if (a == "--serve-ops") {
      serve.ops = std::stoi(v);
    } else {
      std::fprintf(stderr, "bench_durability: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  // The stores go to $TMPDIR (default /tmp): it must be a disk file system, where fdatasync
  // waits for the device (on tmpfs both levels cost the same).
  const char* tmpdir = std::getenv("TMPDIR");
  std::string tmpl = std::string(tmpdir != nullptr && *tmpdir != 0 ? tmpdir : "/tmp") +
                     "/flipper-bench-durability-XXXXXX";
  if (mkdtemp(tmpl.data()) == nullptr) return 1;
  const fs::path tmp = tmpl;
  double load[3] = {0, 0, 0};
  getloadavg(load, 3);
  std::printf(
      "bench_durability: scratch %s on its file system, load average %.2f %.2f %.2f\n"
      "flipper session, one client over pipes: %d rounds x %d defines + %d accepts per "
      "configuration, configurations alternating\n",
      tmp.c_str(), load[0], load[1], load[2], rounds, ops, ops);
  std::map<std::string, Times> times;
  std::map<std::string, dur::ServeTimes> served;
  int rc = 0;
  try {
    for (int r = 0; r < rounds; ++r)
      for (int k = 0; k < 3; ++k) {
        const Level& l = kLevels[(k + r) % 3];
        round(flipper, tmp / ("s" + std::to_string(r) + "-" + std::to_string(k) + ".sqlite"),
              l.durability, l.group, ops, times[l.name]);
      }
    for (const Level& l : kLevels)
      print_times(l.name, times[l.name].accept_ms, times[l.name].define_ms, "");
    std::printf(
        "flipper serve, %d concurrent clients (one session and keep-alive connection each) on %d "
        "kernels: %d rounds x %d defines + %d accepts per client and configuration\n",
        serve.clients, serve.kernels, serve_rounds, serve.ops, serve.ops);
    for (int r = 0; r < serve_rounds; ++r)
      for (int k = 0; k < 3; ++k) {
        const Level& l = kLevels[(k + r) % 3];
        dur::ServeRound one = serve;
        one.level = l.durability;
        one.group = l.group;
        dur::serve_round(flipper,
                         tmp / ("h" + std::to_string(r) + "-" + std::to_string(k) + ".sqlite"), one,
                         served[l.name]);
      }
    for (const Level& l : kLevels) {
      const dur::ServeTimes& t = served[l.name];
      char extra[160];
      if (t.writes > 0)
        std::snprintf(extra, sizeof extra, "   %llu writes, %llu WAL syncs (%.2f per write)",
                      static_cast<unsigned long long>(t.writes),
                      static_cast<unsigned long long>(t.syncs),
                      static_cast<double>(t.syncs) / static_cast<double>(t.writes));
      else
        std::snprintf(extra, sizeof extra, "   %s",
                      l.group ? ""
                              : (std::string(l.durability) == "full" ? "(one sync per write)"
                                                                     : "(no sync per write)"));
      print_times(l.name, t.accept_ms, t.define_ms, extra);
    }
    const std::vector<double> orig = original_query_ms();
    const double o50 = pct(orig, 0.5), o99 = pct(orig, 0.99);
    std::printf(
        "ratio to the original (target >= 20x at p50 and p99): the 2018 server's accept and "
        "define times are not recorded; its own `:q` server time is (walltime_s of %zu dev "
        "queries: p50 %.2f ms, p99 %.1f ms). Shown: that time over Flipper's accept/define round "
        "trip (a proxy: the original kept its lexicon in memory)\n",
        orig.size(), o50, o99);
    for (const Level& l : kLevels)
      print_ratios((std::string("session ") + l.name).c_str(), times[l.name].accept_ms,
                   times[l.name].define_ms, o50, o99);
    for (const Level& l : kLevels)
      print_ratios((std::string("serve ") + l.name).c_str(), served[l.name].accept_ms,
                   served[l.name].define_ms, o50, o99);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_durability: %s\n", e.what());
    rc = 1;
  }
  std::error_code ec;
  fs::remove_all(tmp, ec);
  return rc;
}

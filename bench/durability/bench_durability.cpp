// Accept and define latency of `flipper session` at lexicon.durability: full and normal
// (docs/naturalization.md §5 "Durability and latency"): the round trip of each request over the
// session's pipes (client clock), p50/p99 per level. The levels alternate round by round in one
// run, each round a fresh process and store file in a temporary folder, so that both see the same
// machine (absolute times on a shared machine vary from day to day; the ratio is the figure).
// Each define adds a new head; each accept follows a query of one of those heads.
// Usage: bench_durability [--flipper BIN] [--rounds N] [--ops N]   (stores in $TMPDIR or /tmp)
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "child_process.hpp"

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
void round(const std::string& flipper, const fs::path& store, const std::string& level, int ops,
           Times& into) {
  flipper::testsupport::ChildProcess c({flipper, "session", "--set",
                                        "lexicon.path=" + store.string(), "--set",
                                        "lexicon.durability=" + level});
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

}  // namespace

int main(int argc, char** argv) {
  std::string flipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";
  int rounds = 3, ops = 100;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--flipper") {
      flipper = argv[i + 1];
    } else if (a == "--rounds") {
      rounds = std::stoi(argv[i + 1]);
    } else if (a == "--ops") {
      ops = std::stoi(argv[i + 1]);
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
      "bench_durability: %d rounds x %d accepts + %d defines per level, levels alternating, "
      "scratch %s on its file system, load average %.2f %.2f %.2f\n",
      rounds, ops, ops, tmp.c_str(), load[0], load[1], load[2]);
  std::map<std::string, Times> times;
  int rc = 0;
  try {
    for (int r = 0; r < rounds; ++r) {
      const bool full_first = r % 2 == 0;
      for (const char* level : {full_first ? "full" : "normal", full_first ? "normal" : "full"})
        round(flipper, tmp / (std::string(level) + std::to_string(r) + ".sqlite"), level, ops,
              times[level]);
    }
    for (const char* level : {"full", "normal"}) {
      const Times& t = times[level];
      std::printf(
          "  lexicon.durability=%-6s  accept p50 %7.3f ms  p99 %7.3f ms   define p50 %7.3f ms  "
          "p99 %7.3f ms\n",
          level, pct(t.accept_ms, 0.5), pct(t.accept_ms, 0.99), pct(t.define_ms, 0.5),
          pct(t.define_ms, 0.99));
    }
    const Times& f = times["full"];
    const Times& n = times["normal"];
    std::printf(
        "  normal vs full: accept %.1fx p50 %.1fx p99, define %.1fx p50 %.1fx p99 (target: "
        "accept and define >= 20x the 2018 server at p50 and p99, measured side by side with it "
        "in one run: the 2018 server is not part of this benchmark)\n",
        pct(f.accept_ms, 0.5) / pct(n.accept_ms, 0.5),
        pct(f.accept_ms, 0.99) / pct(n.accept_ms, 0.99),
        pct(f.define_ms, 0.5) / pct(n.define_ms, 0.5),
        pct(f.define_ms, 0.99) / pct(n.define_ms, 0.99));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_durability: %s\n", e.what());
    rc = 1;
  }
  std::error_code ec;
  fs::remove_all(tmp, ec);
  return rc;
}

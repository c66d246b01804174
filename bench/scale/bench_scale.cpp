// bench_scale: the scale table, one row per line, each next to its target (docs/protocol.md §
// "Protocol versions" for the change-only form). Everything it writes goes to a fresh temporary
// directory.
//
//   stream    a recorded session stream built from the dev corpus (every session in order: user,
//             then per query its `world` and `query`, `accept` where the study accepted, `define`
//             where the study defined), replayed in process (thread CPU time per op: the figure
//             the query-p50 target is about) and through `flipper session` (wall time per op over
//             the pipe, peak RSS of the process), in the full and in the change-only form
//   worlds    synthetic 128x128 and 1024x1024 worlds: `world` op, query p50/p99, answer bytes
//   rules     synthetic lexicon stores of 0 / 1k / 10k / 100k rules: start-up, RSS, parse p99
//   long      a 5,000-request session (query + accept): accept p50 early vs late
//   disk      accept/define p50/p99 while another process fsyncs in a loop (disk contention)
//   k50       the same stream with every query asking for k = 50 candidates: server time per
//             query (thread CPU in process; candidate serialisation, docs/protocol.md), and the
//             round trip of a query through `flipper session`'s pipes at the default k and at 50
//
// Usage: bench_scale [--flipper BIN] [--corpus DIR] [--runs N] [--only
// stream,worlds,rules,long,disk,k50]
//                    [--rules 0,1000,10000,100000]
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/wiring/session_factory.hpp"

namespace fs = std::filesystem;
using flipper::kernel::Json;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

namespace {

std::string g_flipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";
std::string kCorpus = std::string(FLIPPER_STUDY_DIR) + "/dev/";
fs::path g_tmp;
int g_runs = 3;

double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) / 1e6;
}
double since_ms(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
double pct(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");  // never "met"
  std::sort(v.begin(), v.end());
  auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}
double median(std::vector<double> v) {
  return pct(std::move(v), 0.5);
}

// ---- the table -----------------------------------------------------------------------------
struct Row {
  std::string what, figure, target;
  int met;  // 1 met, 0 not met, -1 not measured
};
std::vector<Row> g_rows;
void row(const std::string& what, const std::string& figure, const std::string& target, int met) {
  g_rows.push_back({what, figure, target, met});
  std::printf("  %-58s %-34s target %-22s %s\n", what.c_str(), figure.c_str(), target.c_str(),
              met == 1   ? "MET"
              : met == 0 ? "not met"
                         : "n/a");
  std::fflush(stdout);
}
std::string fmt(const char* f, double a, double b = 0) {
  char buf[128];
  std::snprintf(buf, sizeof buf, f, a, b);
  return buf;
}

// ---- a child `flipper session` over pipes ----------------------------------------------------
struct Child {
  pid_t pid = -1;
  int to = -1, from = -1;
  std::string buf;
  explicit Child(const std::vector<std::string>& sets) {
    int in[2], out[2];
    if (pipe(in) != 0 || pipe(out) != 0) throw std::runtime_error("pipe");
    pid = fork();
    if (pid == 0) {
      dup2(in[0], 0);
      dup2(out[1], 1);
      close(in[1]);
      close(out[0]);
      std::vector<std::string> args = {g_flipper, "session"};
      for (const auto& s : sets) args.insert(args.end(), {"--set", s});
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(g_flipper.c_str(), argv.data());
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
      if (poll(&p, 1, 120000) <= 0) throw std::runtime_error("flipper session did not answer");
      char chunk[1 << 16];
      ssize_t n = read(from, chunk, sizeof chunk);
      if (n <= 0) throw std::runtime_error("flipper session closed its output");
      buf.append(chunk, static_cast<std::size_t>(n));
    }
  }
  std::string ask(const std::string& line) {
    send(line);
    return receive();
  }
  double vm_hwm_mib() const {
    std::ifstream st("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(st, line);)
      if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
    return -1;
  }
  ~Child() {
    close(to);
    close(from);
    int status;
    waitpid(pid, &status, 0);
  }
};

bool ok(const std::string& answer) {
  return answer.find("\"ok\":true") != std::string::npos;
}

// ---- the recorded session stream -------------------------------------------------------------
struct Request {
  std::string op, line;
};

std::vector<json> read_jsonl(const std::string& path) {
  std::vector<json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(json::parse(line));
  return out;
}

// The dev corpus as the protocol requests a client would have sent, session by session.
// shown: the "k" of every query request (0: none, the session's default).
std::vector<Request> corpus_stream(int shown = 0) {
  std::map<std::string, json> worlds;
  for (auto& w : read_jsonl(kCorpus + "worlds.jsonl")) {
    json obj;
    for (const char* k : {"walls", "items", "robot", "rooms", "bounds"})
      if (w.contains(k)) obj[k] = w[k];
    worlds[w["world_id"].get<std::string>()] = obj;
  }
  std::map<std::string, json> defs;
  for (auto& d : read_jsonl(kCorpus + "definitions.jsonl"))
    defs[d["def_id"].get<std::string>()] = d;
  std::map<std::string, std::vector<json>> by_session;
  std::vector<std::string> order;
  for (auto& q : read_jsonl(kCorpus + "queries.jsonl")) {
    std::string s = q.value("session", "");
    if (!by_session.count(s)) order.push_back(s);
    by_session[s].push_back(q);
  }
  std::vector<Request> out;
  for (const auto& s : order) {
    const auto& qs = by_session[s];
    out.push_back({"user", json{{"op", "user"}, {"name", qs.front().value("user", s)}}.dump()});
    for (const auto& q : qs) {
      const std::string kind = q.value("kind", "");
      if (kind == "q" && q["utterance"].is_string()) {
        auto w = worlds.find(q.value("world_id", ""));
        if (w != worlds.end())
          out.push_back({"world", json{{"op", "world"}, {"world", w->second}}.dump()});
        json request{{"op", "query"}, {"text", q["utterance"]}};
        if (shown > 0) request["k"] = shown;
        out.push_back({"query", request.dump()});
      } else if (kind == "accept") {
        out.push_back({"accept", R"({"op":"accept","rank":0})"});
      } else if (kind == "def" || kind == "def_ret" || kind == "def_iso") {
        auto d = defs.find("d:" + q.value("qid", ""));
        if (d == defs.end()) continue;
        json body = json::array();
        for (const auto& b : d->second["body"]) body.push_back(b["utterance"]);
        out.push_back(
            {"define", json{{"op", "define"}, {"head", d->second["head"]}, {"body", body}}.dump()});
      }
    }
  }
  return out;
}

// An accept is sent only when the last query has an acceptable first candidate (the study's
// accepts refer to the original's candidates; ours may differ).
bool acceptable(const std::string& query_answer) {
  auto a = json::parse(query_answer);
  if (!a.value("ok", false) || a["candidates"].empty()) return false;
  return !a["candidates"][0].contains("error");
}

const char* kHello2 = R"({"op":"hello","protocol":2})";

struct OpTimes {
  std::map<std::string, std::vector<double>> ms;
  double rss_mib = -1;
  std::size_t bytes = 0, answers = 0;
};

OpTimes replay_in_process(const std::vector<Request>& stream, bool v2, const std::string& store) {
  auto session = flipper::wiring::open_session(std::nullopt, {"lexicon.path=" + store});
  if (v2 && !ok(session->handle_line(kHello2))) return {};
  OpTimes t;
  bool can_accept = false;
  for (const auto& r : stream) {
    if (r.op == "accept" && !can_accept) continue;
    const double c0 = cpu_ms();
    std::string a = session->handle_line(r.line);
    t.ms[r.op].push_back(cpu_ms() - c0);
    t.bytes += a.size();
    ++t.answers;
    if (r.op == "query") can_accept = acceptable(a);
    if (r.op == "accept" || r.op == "world") can_accept = false;
  }
  return t;
}

OpTimes replay_child(const std::vector<Request>& stream, bool v2, const std::string& store) {
  Child c({"lexicon.path=" + store});
  if (v2 && !ok(c.ask(kHello2))) return {};
  OpTimes t;
  bool can_accept = false;
  for (const auto& r : stream) {
    if (r.op == "accept" && !can_accept) continue;
    auto t0 = Clock::now();
    std::string a = c.ask(r.line);
    t.ms[r.op].push_back(since_ms(t0));
    if (r.op == "query") can_accept = acceptable(a);
    if (r.op == "accept" || r.op == "world") can_accept = false;
  }
  t.rss_mib = c.vm_hwm_mib();
  return t;
}

void bench_stream() {
  std::printf("== recorded session stream (dev corpus through the session protocol)\n");
  const auto stream = corpus_stream();
  {
    std::ofstream f(g_tmp / "dev-stream.jsonl");
    for (const auto& r : stream) f << r.line << "\n";
  }
  std::map<std::string, int> counts;
  for (const auto& r : stream) ++counts[r.op];
  std::printf("  stream: %zu requests (%d world, %d query, %d accept, %d define) in %s\n",
              stream.size(), counts["world"], counts["query"], counts["accept"], counts["define"],
              (g_tmp / "dev-stream.jsonl").c_str());
  for (bool v2 : {false, true}) {
    const char* form = v2 ? "change-only form" : "full form";
    std::map<std::string, std::vector<double>> p50s, p99s;
    std::size_t bytes = 0, answers = 0;
    bool supported = true;
    for (int run = 0; run < g_runs; ++run) {
      fs::path store = g_tmp / ("stream-" + std::to_string(v2) + "-" + std::to_string(run));
      OpTimes t = replay_in_process(stream, v2, store.string());
      if (t.answers == 0) {
        supported = false;
        break;
      }
      bytes = t.bytes;
      answers = t.answers;
      for (auto& [op, v] : t.ms) {
        p50s[op].push_back(pct(v, 0.5));
        p99s[op].push_back(pct(v, 0.99));
      }
    }
    if (!supported) {
      row(std::string("query p50, in process (") + form + ")", "not supported", "<= 0.06 ms", 0);
      continue;
    }
    for (const char* op : {"world", "query", "accept", "define"})
      std::printf(
          "    in process, %s, %-6s p50 %8.3f ms  p99 %8.3f ms  (thread CPU, median of %d)\n", form,
          op, median(p50s[op]), median(p99s[op]), g_runs);
    std::printf(
        "    answer bytes: %.0f per answer\n",
        static_cast<double>(bytes) / static_cast<double>(std::max<std::size_t>(1, answers)));
    const double q50 = median(p50s["query"]);
    row(std::string("query p50, real sessions, in process (") + form + ")",
        fmt("%.4f ms (world op p50 %.4f)", q50, median(p50s["world"])), "<= 0.06 ms", q50 <= 0.06);
    // Through the pipe, one run (wall time includes the other processes of a shared machine).
    OpTimes t = replay_child(stream, v2, (g_tmp / ("stream-child-" + std::to_string(v2))).string());
    for (const char* op : {"world", "query", "accept", "define"})
      std::printf("    flipper session, %s, %-6s p50 %8.3f ms  p99 %8.3f ms  (wall, pipe)\n", form,
                  op, pct(t.ms[op], 0.5), pct(t.ms[op], 0.99));
    if (!v2)
      row("peak RSS of one study run (flipper session)", fmt("%.1f MiB", t.rss_mib), "<= 12 MiB",
          t.rss_mib <= 12);
  }
}

// ---- k = 50 ----------------------------------------------------------------------------------
// Server time of a query showing 50 candidates (each executed and written in full) on the study
// stream, and the session protocol's round trip (client clock, pipes) at the default k and at 50.
void bench_k50() {
  constexpr int kShown = 50;
  std::printf("== the study stream at k = %d (candidate serialisation)\n", kShown);
  const auto stream = corpus_stream(kShown);
  std::vector<double> p50s, p99s;
  std::size_t bytes = 0, answers = 0;
  for (int run = 0; run < g_runs; ++run) {
    OpTimes t = replay_in_process(stream, false, (g_tmp / ("k50-" + std::to_string(run))).string());
    p50s.push_back(pct(t.ms["query"], 0.5));
    p99s.push_back(pct(t.ms["query"], 0.99));
    bytes = t.bytes;
    answers = t.answers;
  }
  std::printf(
      "    in process, k = %d, query p50 %8.4f ms  p99 %8.4f ms  (thread CPU, median of %d)\n",
      kShown, median(p50s), median(p99s), g_runs);
  std::printf("    answer bytes: %.0f per answer\n",
              static_cast<double>(bytes) / static_cast<double>(std::max<std::size_t>(1, answers)));
  row("query server time p50 at k = 50, in process",
      fmt("%.4f ms (p99 %.3f)", median(p50s), median(p99s)), "<= 0.020 ms", median(p50s) <= 0.020);
  for (int k : {0, kShown}) {
    std::vector<double> r50, r99;
    for (int run = 0; run < g_runs; ++run) {
      OpTimes t = replay_child(
          k == 0 ? corpus_stream() : stream, false,
          (g_tmp / ("k50-child-" + std::to_string(k) + "-" + std::to_string(run))).string());
      r50.push_back(pct(t.ms["query"], 0.5));
      r99.push_back(pct(t.ms["query"], 0.99));
    }
    const std::string label = k == 0 ? std::string("default k") : "k = " + std::to_string(k);
    std::printf(
        "    flipper session, %s, query round trip p50 %8.3f ms  p99 %8.3f ms  (wall, pipe, "
        "median of %d)\n",
        label.c_str(), median(r50), median(r99), g_runs);
    row("query round trip p99, flipper session pipe, " + label,
        fmt("%.3f ms (p50 %.3f)", median(r99), median(r50)), "<= 1 ms (quiet machine)",
        median(r99) <= 1.0);
  }
}

// ---- big worlds ------------------------------------------------------------------------------
// A size x size world: border walls, wall segments with gaps (rooms of ~16 cells), 24 items, three
// rooms. Deterministic.
json big_world(int size) {
  std::mt19937 rng(7);
  std::set<std::pair<int, int>> walls;
  for (int i = -1; i <= size; ++i) {
    walls.insert({i, -1});
    walls.insert({i, size});
    walls.insert({-1, i});
    walls.insert({size, i});
  }
  for (int x = 16; x < size; x += 16)
    for (int y = 0; y < size; ++y)
      if (y % 16 != 8) walls.insert({x, y});
  for (int y = 16; y < size; y += 16)
    for (int x = 0; x < size; ++x)
      if (x % 16 != 8 && !(x % 16 == 0)) walls.insert({x, y});
  json w;
  w["walls"] = json::array();
  for (auto [x, y] : walls) w["walls"].push_back({x, y});
  const char* colors[] = {"red", "blue", "green", "yellow"};
  const char* shapes[] = {"circle", "square", "triangle"};
  w["items"] = json::array();
  for (int i = 0; i < 24; ++i) {
    int x, y;
    do {
      x = static_cast<int>(rng() % static_cast<unsigned>(size));
      y = static_cast<int>(rng() % static_cast<unsigned>(size));
    } while (walls.count({x, y}));
    w["items"].push_back({{"x", x}, {"y", y}, {"color", colors[i % 4]}, {"shape", shapes[i % 3]}});
  }
  w["robot"] = {{"x", 2}, {"y", 2}, {"holding", json::array()}};
  w["rooms"] = json::object();
  for (int r = 0; r < 3; ++r) {
    json pts = json::array();
    int ox = 17 + 16 * r, oy = 1;
    for (int x = ox; x < ox + 15 && x < size; ++x)
      for (int y = oy; y < oy + 15 && y < size; ++y) pts.push_back({x, y});
    w["rooms"]["room" + std::to_string(r + 1)] = pts;
  }
  w["bounds"] = {{"min", {-1, -1}}, {"max", {size, size}}};
  return w;
}

std::vector<std::string> distinct_utterances(std::size_t n) {
  std::vector<std::string> out;
  std::set<std::string> seen;
  for (auto& q : read_jsonl(kCorpus + "queries.jsonl"))
    if (q.value("kind", "") == "q" && q["utterance"].is_string() &&
        seen.insert(q["utterance"].get<std::string>()).second)
      out.push_back(q["utterance"].get<std::string>());
  // Spread over the corpus rather than its first sessions.
  std::vector<std::string> pick;
  for (std::size_t i = 0; i < n && !out.empty(); ++i) pick.push_back(out[i * out.size() / n]);
  return pick;
}

void bench_worlds() {
  std::printf("== big worlds\n");
  for (int size : {128, 1024}) {
    fs::path file = g_tmp / ("world" + std::to_string(size) + ".json");
    {
      std::ofstream f(file);
      f << big_world(size).dump();
    }
    const std::size_t nq = size == 128 ? 200 : 60;
    const auto utts = distinct_utterances(nq);
    for (bool v2 : {false, true}) {
      const char* form = v2 ? "change-only" : "full";
      auto session = flipper::wiring::open_session(
          std::nullopt,
          {"lexicon.path=" +
           (g_tmp / ("worlds-" + std::to_string(size) + "-" + std::to_string(v2))).string()});
      if (v2 && !ok(session->handle_line(kHello2))) {
        std::printf("  %d^2 %s form: not supported\n", size, form);
        continue;
      }
      const std::string world_line = json{{"op", "world"}, {"file", file.string()}}.dump();
      // A new map: each run in a fresh session (the session keeps a loaded map for a reload).
      std::vector<double> world_ms, reload_ms;
      for (int r = 0; r < std::max(3, g_runs); ++r) {
        auto fresh = flipper::wiring::open_session(
            std::nullopt, {"lexicon.path=" + (g_tmp / ("worlds-fresh-" + std::to_string(size) +
                                                       "-" + std::to_string(r)))
                                                 .string()});
        if (v2) fresh->handle_line(kHello2);
        double c0 = cpu_ms();
        std::string a = fresh->handle_line(world_line);
        world_ms.push_back(cpu_ms() - c0);
        if (!ok(a)) {
          std::printf("  world refused: %.300s\n", a.c_str());
          return;
        }
        c0 = cpu_ms();
        session->handle_line(world_line);
        reload_ms.push_back(cpu_ms() - c0);
      }
      std::vector<double> q_ms;
      std::size_t bytes = 0, max_bytes = 0, budget = 0, max_world_bytes = 0;
      std::vector<std::pair<double, std::string>> slow;
      for (const auto& u : utts) {
        const double c0 = cpu_ms();
        std::string a = session->handle_line(json{{"op", "query"}, {"text", u}}.dump());
        q_ms.push_back(cpu_ms() - c0);
        slow.emplace_back(q_ms.back(), u);
        bytes += a.size();
        max_bytes = std::max(max_bytes, a.size());
        if (a.find("deadline_exceeded") != std::string::npos) ++budget;
        std::size_t world_bytes = 0;
        for (const auto& c : json::parse(a).value("candidates", json::array()))
          world_bytes += c["world"].dump().size();
        max_world_bytes = std::max(max_world_bytes, world_bytes);
      }
      std::sort(slow.rbegin(), slow.rend());
      for (std::size_t i = 0; i < 3 && i < slow.size(); ++i)
        std::printf("      slowest: %8.2f ms  %s\n", slow[i].first, slow[i].second.c_str());
      const std::string label = std::to_string(size) + "^2 world, " + form + " form";
      std::printf(
          "    %s: query p50 %.3f ms, answers mean %.0f / max %zu bytes, %zu at the deadline\n",
          label.c_str(), pct(q_ms, 0.5),
          static_cast<double>(bytes) / static_cast<double>(utts.size()), max_bytes, budget);
      std::printf("    %s: world op new map %.3f ms, same map again %.3f ms\n", label.c_str(),
                  median(world_ms), median(reload_ms));
      if (size == 128) {
        row(label + ": world op (new map)", fmt("%.3f ms", median(world_ms)), "<= 1 ms",
            median(world_ms) <= 1);
        row(label + ": query p99", fmt("%.2f ms", pct(q_ms, 0.99)), "<= 10 ms",
            pct(q_ms, 0.99) <= 10);
      } else {
        row(label + ": world op (new map)", fmt("%.1f ms", median(world_ms)), "(no target)", -1);
        row(label + ": query p99", fmt("%.2f ms", pct(q_ms, 0.99)), "<= 50 ms",
            pct(q_ms, 0.99) <= 50);
        // Independent of the wall count: the worlds of an answer far smaller than the walls.
        const double wall_bytes = static_cast<double>(fs::file_size(file));
        row(label + ": worlds in the largest answer",
            fmt("%.1f KiB (map file %.0f KiB)", static_cast<double>(max_world_bytes) / 1024.0,
                wall_bytes / 1024.0),
            "< 1% of the map", static_cast<double>(max_world_bytes) * 100 < wall_bytes);
      }
    }
  }
}

// ---- lexicon sizes -----------------------------------------------------------------------------
// N induced rules shaped like real definitions (bench/parser's shapes), committed in batches.
void populate(const std::string& path, int n) {
  flipper::naturalization::LexiconStore store(path);
  std::mt19937 rng(42);
  const std::vector<std::string> common = {"pick",  "drop", "visit", "move", "go",  "all",  "the",
                                           "items", "red",  "room1", "to",   "and", "then", "left"};
  auto word = [&](int i) {
    return rng() % 3 == 0 ? common[rng() % common.size()] : "w" + std::to_string(i % 997) + "x";
  };
  std::int64_t created = store.max_created();
  for (int done = 0; done < n;) {
    std::vector<flipper::naturalization::StoredRule> batch;
    for (int j = 0; j < 1000 && done < n; ++j, ++done) {
      flipper::naturalization::StoredRule r;
      r.created = ++created;
      r.id = "r" + std::to_string(r.created);
      r.lhs = "$Action";
      switch (done % 5) {
        case 0:
          r.rhs = {"pick", "$Number", word(done), "items"};
          r.semantics = "{repeat $1 times {pick item}}";
          break;
        case 1:
          r.rhs = {"visit", "$Color", "$Shape", word(done)};
          r.semantics = "{visit {world containing item {{is $1} and {is $2}}}}";
          break;
        case 2:
          r.rhs = {word(done), word(done + 1), "$Area"};
          r.semantics = "{visit $1}";
          break;
        case 3:
          r.rhs = {word(done), "$Direction", word(done + 7)};
          r.semantics = "{repeat 2 times {move $1}}";
          break;
        default:
          r.rhs = {"gather", "$Color", word(done)};
          r.semantics = "{visit {world containing item {is $1}}}";
      }
      r.author = "u" + std::to_string(rng() % 37);
      r.head = "synthetic";
      r.body = {"synthetic"};
      r.how = "best";
      batch.push_back(std::move(r));
    }
    store.add_definition({0, "synthetic", {"synthetic"}, "bench", 0}, batch);
  }
}

void bench_rules(const std::vector<int>& sizes) {
  std::printf("== lexicon sizes (synthetic stores)\n");
  const auto utts = distinct_utterances(150);
  for (int n : sizes) {
    const std::string store = (g_tmp / ("rules-" + std::to_string(n) + ".sqlite")).string();
    auto t0 = Clock::now();
    populate(store, n);
    std::printf("  %d rules: store written in %.1f s (%.1f MiB)\n", n, since_ms(t0) / 1000,
                static_cast<double>(fs::file_size(store)) / (1 << 20));
    std::vector<double> startup;
    double rss = -1;
    for (int r = 0; r < std::max(3, g_runs); ++r) {
      auto s0 = Clock::now();
      Child c({"lexicon.path=" + store});
      std::string a = c.ask(R"({"op":"user","name":"u1"})");
      startup.push_back(since_ms(s0));
      if (!ok(a)) throw std::runtime_error("flipper session refused: " + a);
      if (r == 0) {
        for (std::size_t i = 0; i < 20; ++i) c.ask(json{{"op", "query"}, {"text", utts[i]}}.dump());
        rss = c.vm_hwm_mib();
      }
    }
    // The parser alone, in process, over the same store.
    auto session = flipper::wiring::open_session(std::nullopt, {"lexicon.path=" + store});
    auto& rt = session->runtime();
    std::vector<double> parse_ms;
    for (const auto& u : utts) {
      flipper::sdk::ParseRequest pr;
      pr.tokens = flipper::sdk::tokenize(u);
      pr.context.tokens = &pr.tokens;
      pr.context.user = "u1";
      pr.scorer = rt.scorer.borrow();
      const double c0 = cpu_ms();
      auto result = rt.parser.borrow()->parse(pr);
      parse_ms.push_back(cpu_ms() - c0);
    }
    const std::string label = std::to_string(n) + " rules";
    std::printf("    %s: start-up median %.1f ms, RSS %.1f MiB, parse p50 %.3f p99 %.3f ms\n",
                label.c_str(), median(startup), rss, pct(parse_ms, 0.5), pct(parse_ms, 0.99));
    // The first start reads the rows and leaves the rule snapshot the others start from
    // (docs/naturalization.md §5 "Start-up at scale"); RSS is that first start's.
    std::printf("    %s: first start (rows read, snapshot written) %.1f ms, later starts:",
                label.c_str(), startup.front());
    for (std::size_t i = 1; i < startup.size(); ++i) std::printf(" %.1f", startup[i]);
    std::printf(" ms\n");
    if (n == 10000 || n == 100000) {
      const bool big = n == 100000;
      row(label + ": RSS", fmt("%.1f MiB", rss), big ? "<= 150 MiB" : "<= 30 MiB",
          rss <= (big ? 150 : 30));
      // Start-up to the first answer; 100k: at most 0.25 s (the earlier 300 ms, tightened).
      row(label + ": start-up", fmt("%.0f ms", median(startup)), big ? "<= 250 ms" : "<= 30 ms",
          median(startup) <= (big ? 250 : 30));
      if (big)
        row(label + ": parse p99 (parser alone)", fmt("%.2f ms", pct(parse_ms, 0.99)), "<= 10 ms",
            pct(parse_ms, 0.99) <= 10);
    }
  }
}

// ---- one long session ------------------------------------------------------------------------
void bench_long() {
  std::printf("== a 5,000-request session (query + accept, dev utterances in turn)\n");
  const auto utts = distinct_utterances(600);
  Child c({"lexicon.path=" + (g_tmp / "long.sqlite").string()});
  std::vector<double> accept_ms;
  int requests = 0;
  for (std::size_t i = 0; requests < 5000; ++i) {
    if (i % 50 == 0) {  // back to the study map now and then: the robot should not get stuck
      c.ask(R"({"op":"world","file":"configs/worlds/study2018.json"})");
      ++requests;
    }
    std::string a = c.ask(json{{"op", "query"}, {"text", utts[i % utts.size()]}}.dump());
    ++requests;
    if (!acceptable(a)) continue;
    auto t0 = Clock::now();
    std::string b = c.ask(R"({"op":"accept","rank":0})");
    accept_ms.push_back(since_ms(t0));
    ++requests;
  }
  const std::size_t w = std::min<std::size_t>(200, accept_ms.size() / 2);
  std::vector<double> early(accept_ms.begin(), accept_ms.begin() + static_cast<long>(w));
  std::vector<double> late(accept_ms.end() - static_cast<long>(w), accept_ms.end());
  const double e = median(early), l = median(late);
  row("accept p50 over 5,000 requests: first vs last 200", fmt("%.2f -> %.2f ms", e, l),
      "flat (late <= 1.25x early)", l <= 1.25 * e);
}

// ---- disk contention -------------------------------------------------------------------------
void bench_disk() {
  std::printf("== accept/define while another thread fsyncs in a loop\n");
  std::atomic<bool> stop{false};
  std::thread hammer([&] {
    const std::string path = (g_tmp / "hammer.bin").string();
    std::vector<char> block(1 << 18, 'x');
    FILE* f = std::fopen(path.c_str(), "w");
    while (!stop) {
      std::fwrite(block.data(), 1, block.size(), f);
      std::fflush(f);
      fsync(fileno(f));
      if (std::ftell(f) > (64 << 20)) std::rewind(f);
    }
    std::fclose(f);
  });
  const auto utts = distinct_utterances(300);
  Child c({"lexicon.path=" + (g_tmp / "disk.sqlite").string()});
  std::vector<double> accept_ms, define_ms;
  for (std::size_t i = 0; accept_ms.size() < 200 && i < 3000; ++i) {
    if (i % 40 == 0) c.ask(R"({"op":"world","file":"configs/worlds/study2018.json"})");
    std::string a = c.ask(json{{"op", "query"}, {"text", utts[i % utts.size()]}}.dump());
    if (!acceptable(a)) continue;
    auto t0 = Clock::now();
    c.ask(R"({"op":"accept","rank":0})");
    accept_ms.push_back(since_ms(t0));
  }
  for (int i = 0; i < 60; ++i) {
    auto t0 = Clock::now();
    std::string a = c.ask(json{{"op", "define"},
                               {"head", "zq" + std::to_string(i) + " move"},
                               {"body", {"move left", "move right"}}}
                              .dump());
    define_ms.push_back(since_ms(t0));
    if (!ok(a) && i == 0) std::printf("  define refused: %.300s\n", a.c_str());
  }
  stop = true;
  hammer.join();
  std::printf("    accept p50 %.2f p99 %.2f ms, define p50 %.2f p99 %.2f ms\n", pct(accept_ms, 0.5),
              pct(accept_ms, 0.99), pct(define_ms, 0.5), pct(define_ms, 0.99));
  row("accept p99 under disk contention",
      fmt("%.2f ms (p50 %.2f)", pct(accept_ms, 0.99), pct(accept_ms, 0.5)), "<= 5 ms",
      pct(accept_ms, 0.99) <= 5);
  row("define p99 under disk contention",
      fmt("%.2f ms (p50 %.2f)", pct(define_ms, 0.99), pct(define_ms, 0.5)), "<= 5 ms",
      pct(define_ms, 0.99) <= 5);
}

}  // namespace

int main(int argc, char** argv) {
  std::string only = "stream,worlds,rules,long,disk,k50";
  std::vector<int> sizes = {0, 1000, 10000, 100000};
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string a = argv[i];
    if (a == "--flipper")
      g_flipper = argv[i + 1];
    else if (a == "--corpus")
      kCorpus = std::string(argv[i + 1]) + "/";
    else if (a == "--runs")
      g_runs = std::stoi(argv[i + 1]);
    else if (a == "--only")
      only = argv[i + 1];
    else if (a == "--rules") {
      sizes.clear();
      std::stringstream ss(argv[i + 1]);
      for (std::string s; std::getline(ss, s, ',');) sizes.push_back(std::stoi(s));
    } else {
      std::fprintf(stderr, "bench_scale: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (!fs::exists(kCorpus + "queries.jsonl")) {
    std::fprintf(stderr, "bench_scale: no dev corpus at %s (give --corpus DIR)\n", kCorpus.c_str());
    return 2;
  }
  char tmpl[] = "/tmp/flipper-bench-scale-XXXXXX";
  if (mkdtemp(tmpl) == nullptr) return 1;
  g_tmp = tmpl;
  double load[3] = {0, 0, 0};
  getloadavg(load, 3);
  std::printf("bench_scale: scratch %s, load average %.2f %.2f %.2f, %d run(s) per median\n",
              g_tmp.c_str(), load[0], load[1], load[2], g_runs);
  auto want = [&](const char* s) { return only.find(s) != std::string::npos; };
  int rc = 0;
  try {
    if (want("stream")) bench_stream();
    if (want("worlds")) bench_worlds();
    if (want("rules")) bench_rules(sizes);
    if (want("long")) bench_long();
    if (want("disk")) bench_disk();
    if (want("k50")) bench_k50();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_scale: %s\n", e.what());
    rc = 1;
  }
  getloadavg(load, 3);
  int met = 0, measured = 0;
  std::printf("\n== scale table (load average at the end %.2f)\n", load[0]);
  for (const auto& r : g_rows) {
    std::printf("  %-58s %-34s target %-22s %s\n", r.what.c_str(), r.figure.c_str(),
                r.target.c_str(),
                r.met == 1   ? "MET"
                : r.met == 0 ? "not met"
                             : "n/a");
    if (r.met >= 0) ++measured;
    if (r.met == 1) ++met;
  }
  std::printf("  %d of %d targets met\n", met, measured);
  if (std::getenv("FLIPPER_BENCH_KEEP") == nullptr)
    fs::remove_all(g_tmp);
  else
    std::printf("kept %s (FLIPPER_BENCH_KEEP)\n", g_tmp.c_str());
  return rc;
}

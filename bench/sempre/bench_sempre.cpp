// Latency of `:q` through /sempre (docs/sempre.md) over the dev corpus, as the 2018 client sends
// it: each run of the split on its own `flipper serve --set serve.sempre=true` with the run's
// study keys (flipper replay's mode keys, induction.generalize=false, the run's preloaded expert
// definitions), every logged command of the run in log order from its logged sessionId, each
// query preceded by its context. The round trip of every `:q` (client clock, loopback, one
// keep-alive connection) gives p50/p99; the target is the original server's own time for the
// same queries (walltime_s in queries.jsonl: p50 2.08 ms, p99 35.2 ms), which did not include
// HTTP. The server's own time for each `:q` (stats.walltime: the command from the parsed request to
// the candidates ready to write, k = 50 as the original's cap) gives the server-time p50/p99
// (target p50 <= 20 us, docs/sempre.md).
// --answers FILE writes every answer body, stats.walltime masked to 0, one a line (to compare the
// bytes of two builds).
// Usage: bench_sempre --flipper BIN [--corpus DIR] [--answers FILE]
#include <httplib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "child_process.hpp"
#include "flipper/replay/corpus.hpp"
#include "flipper/replay/replayer.hpp"
#include "sempre_wire.hpp"

namespace {

using flipper::bench::percentile;

using Clock = std::chrono::steady_clock;
using nlohmann::json;
namespace replay = flipper::replay;

struct Run {
  std::vector<double> query_ms, context_ms, original_ms, server_ms;
  long errors = 0;
  std::ofstream* answers = nullptr;
};

// The body with the number after "walltime": replaced by 0 (the one field that varies).
std::string mask_walltime(const std::string& body) {
  const std::string key = "\"walltime\":";
  const auto at = body.find(key);
  if (at == std::string::npos) return body;
  auto end = body.find_first_not_of("0123456789.eE+-", at + key.size());
  if (end == std::string::npos) end = body.size();
  return body.substr(0, at + key.size()) + "0" + body.substr(end);
}

// stats.walltime in ms, or -1.
double server_ms(const std::string& body) {
  const json b = json::parse(body, nullptr, false);
  if (!b.is_object() || !b.contains("stats") || !b["stats"].contains("walltime") ||
      !b["stats"]["walltime"].is_number())
    return -1;
  return b["stats"]["walltime"].get<double>() * 1000.0;
}

void bench_run(const std::string& flipper, const replay::Corpus& corpus, const replay::Run& run,
               const std::map<std::string, std::string>& raw, Run& out) {
  char tmpl[] = "/tmp/flipper-bench-sempre-XXXXXX";
  const std::string dir = ::mkdtemp(tmpl);
  std::vector<std::string> args{flipper, "serve",        "--set", "serve.host=127.0.0.1",
                                "--set", "serve.port=0", "--set", "serve.sempre=true"};
  std::vector<std::string> sets = replay::mode_overrides(run.group);
  for (auto& k : replay::alignment_overrides(corpus, run)) sets.push_back(std::move(k));
  for (auto& k : replay::view_overrides(corpus, run)) sets.push_back(std::move(k));
  sets.push_back("induction.generalize=false");
  // Every logged sessionId comes from this one address, as fast as the server answers.
  for (const char* key : {"serve.sessions_per_address", "serve.new_sessions_per_minute",
                          "serve.new_guests_per_minute", "serve.sessions_per_subnet",
                          "serve.rate_per_second", "serve.rate_burst"})
    sets.push_back(std::string(key) + "=100000");
  if (run.group == "C") {
    const std::string file = dir + "/preload.jsonl";
    std::ofstream p(file);
    for (const auto* d : corpus.preloaded(run.source)) {
      json body = json::array();
      for (const auto& b : d->body) body.push_back(b.utterance);
      p << json{{"head", d->head}, {"body", body}, {"author", d->author()}}.dump() << "\n";
    }
    sets.push_back("lexicon.preload=" + file);
  }
  for (const auto& s : sets) {
    args.push_back("--set");
    args.push_back(s);
  }
  flipper::testsupport::ChildProcess server(args);
  const std::string line = server.read_line(std::chrono::seconds(60));
  const auto at = line.find("127.0.0.1:");
  if (at == std::string::npos) {
    std::cerr << "bench_sempre: the server did not start: " << line << "\n";
    ++out.errors;
    return;
  }
  httplib::Client c("127.0.0.1", std::stoi(line.substr(at + 10)));
  c.set_keep_alive(true);
  c.set_tcp_nodelay(true);
  c.set_read_timeout(60);
  c.set_url_encode(false);  // sempre_target encodes as the browser does
  auto get = [&](const std::string& command, const std::string& session, bool query = false) {
    const auto t0 = Clock::now();
    auto res = c.Get(flipper::sempretest::sempre_target(command, session).c_str());
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (!res || res->status != 200) ++out.errors;
    if (res && query) out.server_ms.push_back(server_ms(res->body));
    if (res && out.answers != nullptr) *out.answers << mask_walltime(res->body) << "\n";
    return ms;
  };
  for (const std::size_t i : run.commands) {
    const replay::Command& cmd = corpus.commands[i];
    if (cmd.kind == "q") {
      const auto world = corpus.worlds.find(cmd.world_id);
      if (world != corpus.worlds.end())
        out.context_ms.push_back(
            get(flipper::sempretest::context_command(world->second), cmd.session));
      out.query_ms.push_back(get(raw.at(cmd.qid), cmd.session, true));
      out.original_ms.push_back(cmd.walltime_s * 1000.0);
    } else {
      get(raw.at(cmd.qid), cmd.session);
    }
  }
  server.kill_now();
  std::filesystem::remove_all(dir);
}

}  // namespace

int main(int argc, char** argv) {
  std::string flipper, corpus_dir = FLIPPER_STUDY_DIR "/dev", answers;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--flipper")
      flipper = v;
    else if (k == "--corpus")
      corpus_dir = v;
    else if (k == "--answers")
      answers = v;
    else {
      std::cerr << "bench_sempre: unknown option " << k << "\n";
      return 2;
    }
  }
  if (flipper.empty()) {
    std::cerr << "usage: bench_sempre --flipper BIN [--corpus DIR] [--answers FILE]\n";
    return 2;
  }
  const replay::Corpus corpus = replay::load_corpus(corpus_dir);
  std::map<std::string, std::string> raw;  // qid -> the logged command
  {
    std::ifstream in(corpus_dir + "/queries.jsonl");
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) {
        const json r = json::parse(line);
        raw.emplace(r["qid"].get<std::string>(), r["raw"].get<std::string>());
      }
  }
  Run all;
  std::ofstream answers_file;
  if (!answers.empty()) {
    answers_file.open(answers);
    all.answers = &answers_file;
  }
  const auto start = Clock::now();
  for (const auto& run : corpus.runs) bench_run(flipper, corpus, run, raw, all);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double p50 = percentile(all.query_ms, 0.5), p99 = percentile(all.query_ms, 0.99);
  const double o50 = percentile(all.original_ms, 0.5), o99 = percentile(all.original_ms, 0.99);
  std::printf(
      "/sempre :q over the dev corpus: %zu queries (%zu runs), %ld errors (target 0), "
      "%.1f s in all\n",
      all.query_ms.size(), corpus.runs.size(), all.errors, seconds);
  std::printf("  :q round trip       p50 %.2f ms (target <= %.2f), p99 %.2f ms (target <= %.2f)\n",
              p50, o50, p99, o99);
  std::printf("  :context round trip p50 %.2f ms, p99 %.2f ms (the 2018 map, sent before each)\n",
              percentile(all.context_ms, 0.5), percentile(all.context_ms, 0.99));
  std::printf("  the original server (walltime_s): p50 %.2f ms, p99 %.2f ms, without HTTP\n", o50,
              o99);
  const double s50 = percentile(all.server_ms, 0.5), s99 = percentile(all.server_ms, 0.99);
  std::printf(
      "  :q server time (stats.walltime, k = 50) p50 %.4f ms (target <= 0.020), p99 %.3f ms %s\n",
      s50, s99, !all.server_ms.empty() && s50 <= 0.020 ? "MET" : "not met");
  if (answers_file.is_open() && !answers_file.flush()) {
    std::cerr << "bench_sempre: cannot write " << answers << "\n";
    return 1;
  }
  return all.errors == 0 ? 0 : 1;
}

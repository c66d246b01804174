// bench_durability's `flipper serve` part (serve_part.hpp).
#include "serve_part.hpp"

#include <httplib.h>
#include <signal.h>

#include <chrono>
#include <mutex>
#include <nlohmann/json.hpp>
#include <regex>
#include <stdexcept>
#include <thread>

#include "child_process.hpp"

namespace flipper::bench::durability {

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

double since_ms(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// One client: its own session on one keep-alive connection; `ops` defines of new heads, then a
/// query of each head and an accept of its first reading (the induced rule's use counter and the
/// scorer's changed weights are written).
void client(int me, int port, const ServeRound& round, ServeTimes& into, std::mutex& mutex,
            std::string& error) {
  httplib::Client http("127.0.0.1", port);
  http.set_read_timeout(120);
  http.set_tcp_nodelay(true);
  http.set_keep_alive(true);
  std::string session;
  auto ask = [&](const json& req) {
    const std::string path =
        session.empty() ? "/api/v1/request" : "/api/v1/request?session=" + session;
    auto res = http.Post(path, req.dump(), "application/json");
    if (!res) throw std::runtime_error("no answer to " + req.dump());
    if (session.empty()) session = res->get_header_value("Flipper-Session");
    json a = json::parse(res->body);
    if (!a.value("ok", false))
      throw std::runtime_error("not ok: " + req.dump() + " -> " + res->body.substr(0, 300));
    return a;
  };
  std::vector<double> defines, accepts;
  try {
    ask(json{{"op", "state"}});
    auto head = [me](int i) {
      return "zq" + std::to_string(me) + "x" + std::to_string(i) + " hop";
    };
    for (int i = 0; i < round.ops; ++i) {
      const json define{{"op", "define"}, {"head", head(i)}, {"body", {"move left", "move right"}}};
      const auto t0 = Clock::now();
      ask(define);
      defines.push_back(since_ms(t0));
    }
    for (int i = 0; i < round.ops; ++i) {
      ask(json{{"op", "query"}, {"text", head(i)}});
      const auto t0 = Clock::now();
      ask(json{{"op", "accept"}, {"rank", 0}});
      accepts.push_back(since_ms(t0));
    }
  } catch (const std::exception& e) {
    const std::lock_guard<std::mutex> lock(mutex);
    if (error.empty()) error = e.what();
  }
  const std::lock_guard<std::mutex> lock(mutex);
  into.define_ms.insert(into.define_ms.end(), defines.begin(), defines.end());
  into.accept_ms.insert(into.accept_ms.end(), accepts.begin(), accepts.end());
}

}  // namespace

void serve_round(const std::string& flipper, const std::filesystem::path& store,
                 const ServeRound& round, ServeTimes& into) {
  std::vector<std::string> args{flipper, "serve"};
  args.reserve(18);
  for (const std::string& s :
       {std::string("serve.host=127.0.0.1"), std::string("serve.port=0"),
        "lexicon.path=" + store.string(), std::string("lexicon.preload="),
        "lexicon.durability=" + round.level,
        std::string("lexicon.group_commit=") + (round.group ? "true" : "false"),
        "serve.kernels=" + std::to_string(round.kernels),
        "serve.threads=" + std::to_string(round.clients + 2)}) {
    args.emplace_back("--set");
    args.push_back(s);
  }
  testsupport::ChildProcess server(args);
  const std::string line = server.read_line(std::chrono::seconds(60));
  const auto at = line.find("127.0.0.1:");
  if (at == std::string::npos) throw std::runtime_error("flipper serve did not start: " + line);
  const int port = std::stoi(line.substr(at + 10));
  std::mutex mutex;
  std::string error;
  std::vector<std::thread> clients;
  clients.reserve(static_cast<std::size_t>(round.clients));
  for (int c = 0; c < round.clients; ++c)
    clients.emplace_back(client, c, port, std::cref(round), std::ref(into), std::ref(mutex),
                         std::ref(error));
  for (auto& t : clients) t.join();
  ::kill(server.pid(), SIGTERM);
  const int status = server.finish();
  const std::string out = server.read_all();
  if (!error.empty()) throw std::runtime_error(error);
  if (status != 0) throw std::runtime_error("flipper serve did not exit 0");
  std::smatch m;
  if (std::regex_search(out, m, std::regex("lexicon group commit: (\\d+) writes, (\\d+) syncs"))) {
    into.writes += std::stoull(m[1]);
    into.syncs += std::stoull(m[2]);
  }
}

}  // namespace flipper::bench::durability

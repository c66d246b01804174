#pragma once
// What the parts of bench_serve share (bench/serve/bench_serve.cpp): a `flipper serve` child on a
// free loopback port with its lexicon in a temporary folder, timing and /proc readings, and one
// protocol request.
#include <httplib.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "child_process.hpp"

namespace flipper::bench::serve {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// ~0.4 s of CPU on the default world (measured with flipper run: docs/studio.md §5).
inline const char* kHeavy =
    "repeat 13 times { foreach point in world { foreach point in world { visit point } } }";

inline double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

inline std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

inline long rss_kib(int pid, const char* field = "VmRSS:") {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(field, 0) == 0) return std::stol(line.substr(std::string(field).size()));
  return -1;
}

struct Server {
  std::unique_ptr<flipper::testsupport::ChildProcess> child;
  int port = 0;
  std::string dir;
  Server(const std::string& flipper, const std::vector<std::string>& sets) {
    char tmpl[] = "/tmp/flipper-bench-serve-XXXXXX";
    dir = ::mkdtemp(tmpl);
    std::vector<std::string> args{flipper, "serve",
                                  "--set", "serve.port=0",
                                  "--set", "lexicon.path=" + dir + "/lexicon.sqlite",
                                  "--set", "lexicon.preload="};
    for (const auto& s : sets) {
      args.push_back("--set");
      args.push_back(s);
    }
    // More --set values for every server, e.g. BENCH_SERVE_SET=serve.kernels=2 (one value).
    if (const char* extra = std::getenv("BENCH_SERVE_SET")) {
      args.push_back("--set");
      args.push_back(extra);
    }
    child = std::make_unique<flipper::testsupport::ChildProcess>(args);
    const std::string line = child->read_line(30s);
    port = std::stoi(line.substr(line.find("127.0.0.1:") + 10));
  }
  ~Server() {
    child->kill_now();
    std::filesystem::remove_all(dir);
  }
  httplib::Client client() const {
    httplib::Client c("127.0.0.1", port);
    c.set_tcp_nodelay(true);
    c.set_read_timeout(60);
    c.set_keep_alive(true);
    return c;
  }
};

inline std::string session_of(httplib::Client& c) {
  auto r = c.Post("/api/v1/request", R"({"op":"state"})", "application/json");
  return r ? r->get_header_value("Flipper-Session") : "";
}

// The round trip in ms; `kernel_ms` gets the query's own time in the kernel (the answer's "ms").
inline double query_ms(httplib::Client& c, const std::string& session, const std::string& text,
                       bool* ok, double* kernel_ms = nullptr) {
  const auto t0 = Clock::now();
  auto r = c.Post(("/api/v1/request?session=" + session).c_str(),
                  nlohmann::json{{"op", "query"}, {"text", text}}.dump(), "application/json");
  if (ok) *ok = r && r->status == 200 && r->body.rfind("{\"ok\":true", 0) == 0;
  if (kernel_ms && r) {
    const auto a = nlohmann::json::parse(r->body, nullptr, false);
    *kernel_ms = a.is_object() ? a.value("ms", 0.0) : 0.0;
  }
  if (ok && !*ok && std::getenv("BENCH_SERVE_DEBUG"))
    std::cerr << (r ? std::to_string(r->status) + " " + r->body.substr(0, 200) : "no answer")
              << "\n";
  return ms_since(t0);
}

/// The login flood and the session flood from many addresses (floods.cpp).
void login_flood(const std::string& flipper);
void session_flood(const std::string& flipper);

}  // namespace flipper::bench::serve

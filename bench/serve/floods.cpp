// The flood figures of `flipper serve` (docs/studio.md §4 "Admission"), each next to its target:
// while many loopback source addresses attack (10 s, logins 30 s), how many new users get in and
// how long another user waits. Every attacking or probing request is one connection from a chosen
// source address (raw_socket.hpp); the addresses span ten /24 subnets, so per-address and
// per-subnet limits alone cannot hold them.
//   login     60 addresses send wrong-password logins for ana as fast as answers come (30 s);
//             meanwhile a logged-in user's GET /api/v1/info every 100 ms (round trip), a new
//             guest from a fresh address every 250 ms and ana's own login from a fresh address
//             every 500 ms (admitted per cent, its round trip)
//   session   40 addresses open new guest sessions as fast as answers come; meanwhile a new
//             guest from a fresh address every 250 ms and a new session of logged-in ana every
//             250 ms (admitted per cent), and the attackers' sessions admitted
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <mutex>
#include <regex>
#include <stdexcept>
#include <thread>

#include "bench_common.hpp"
#include "raw_socket.hpp"
#include "serve_support.hpp"

namespace flipper::bench::serve {
namespace {

using flipper::studiotest::RawSocket;

constexpr auto kAttack = 10s;
// Longer: the first round of 60 password checks alone takes ~6 s.
constexpr auto kLoginAttack = 30s;
const std::string kAnaPassword = "ana's long password";

struct Answer {
  int status = 0;  ///< 0: no answer
  std::string text;
};

// One request on its own connection from `source`; the whole answer (the server closes).
Answer http_once(int port, const std::string& source, const std::string& method,
                 const std::string& path, const std::string& body,
                 const std::string& headers = "") {
  RawSocket s(port, source);
  if (!s.connected()) return {};
  if (!s.send(method + " " + path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
              "\r\nContent-Type: application/json\r\nContent-Length: " +
              std::to_string(body.size()) + "\r\nConnection: close\r\n" + headers + "\r\n" + body))
    return {};
  Answer a;
  a.text = s.read_all(30s);
  if (a.text.size() > 12 && a.text.rfind("HTTP/1.1 ", 0) == 0)
    a.status = std::stoi(a.text.substr(9, 3));
  return a;
}

// The flipper_login cookie of a login answer ("" when refused).
std::string login_cookie(const Answer& a) {
  std::smatch m;
  if (a.status != 200 ||
      !std::regex_search(a.text, m,
                         std::regex("\r\nSet-Cookie: *(flipper_login=[^;\r]*)", std::regex::icase)))
    return "";
  return m[1];
}

std::string login_body(const std::string& password) {
  return nlohmann::json{{"name", "ana"}, {"password", password}}.dump();
}

// Source address number `i` of a group: 127.<group>.<i / 6>.<i % 6 + 1>, six to a /24 (60
// addresses span ten /24s).
std::string address(int group, int i) {
  return "127." + std::to_string(group) + "." + std::to_string(i / 6 % 250) + "." +
         std::to_string(i % 6 + 1);
}

struct Rate {
  std::atomic<int> tried{0}, admitted{0};
  double percent() const { return tried ? 100.0 * admitted / tried : 0; }
};

// Runs `probe` every `every` until `stop`.
template <class Probe>
std::thread every(std::chrono::milliseconds period, const std::atomic<bool>& stop, Probe probe) {
  return std::thread([period, &stop, probe]() mutable {
    for (int i = 0; !stop; ++i) {
      const auto next = Clock::now() + period;
      probe(i);
      std::this_thread::sleep_until(next);
    }
  });
}

void add_ana(const Server& s, const std::string& flipper) {
  const std::string command =
      flipper + " accounts add ana --set lexicon.path=" + s.dir + "/lexicon.sqlite >/dev/null";
  FILE* p = ::popen(command.c_str(), "w");
  if (p == nullptr) throw std::runtime_error("cannot run " + command);
  std::fputs((kAnaPassword + "\n").c_str(), p);
  if (::pclose(p) != 0) throw std::runtime_error(command + " failed");
}

}  // namespace

void login_flood(const std::string& flipper) {
  Server s(flipper, {});
  add_ana(s, flipper);
  const std::string ana = login_cookie(
      http_once(s.port, "127.0.0.1", "POST", "/api/v1/login", login_body(kAnaPassword)));
  std::atomic<bool> stop{false};
  std::atomic<long> attempts{0}, limited{0};
  std::vector<std::thread> attackers;
  attackers.reserve(60);
  for (int a = 0; a < 60; ++a)
    attackers.emplace_back([&, a] {
      while (!stop) {
        const Answer r = http_once(s.port, address(10, a), "POST", "/api/v1/login",
                                   login_body("a wrong password"));
        ++attempts;
        limited += r.status == 429;
      }
    });
  std::vector<double> info_ms;
  std::mutex info_mutex;
  Rate guests, logins;
  std::vector<std::thread> probes;
  probes.push_back(every(100ms, stop, [&](int) {
    const auto t0 = Clock::now();
    const Answer r =
        http_once(s.port, "127.0.0.1", "GET", "/api/v1/info", "", "Cookie: " + ana + "\r\n");
    const double ms = ms_since(t0);
    const std::lock_guard<std::mutex> lock(info_mutex);
    info_ms.push_back(r.status == 200 ? ms : 1e9);
  }));
  probes.push_back(every(250ms, stop, [&](int i) {
    ++guests.tried;
    guests.admitted +=
        http_once(s.port, address(20, i), "POST", "/api/v1/request", R"({"op":"state"})").status ==
        200;
  }));
  std::vector<double> login_ms;  // the login probe's thread only
  probes.push_back(every(500ms, stop, [&](int i) {
    ++logins.tried;
    const auto t0 = Clock::now();
    logins.admitted += !login_cookie(http_once(s.port, address(30, i), "POST", "/api/v1/login",
                                               login_body(kAnaPassword)))
                            .empty();
    login_ms.push_back(ms_since(t0));
  }));
  std::this_thread::sleep_for(kLoginAttack);
  stop = true;
  for (auto& t : attackers) t.join();
  for (auto& t : probes) t.join();
  std::printf(
      "login     60 addresses flood wrong-password logins for 30 s (%ld attempts, %ld refused "
      "429): a logged-in user's GET /api/v1/info (%zu) p50 %.1f ms, p99 %.1f ms, max %.1f ms "
      "(target p99 <= 50 ms); new guests admitted %.0f %% (%d/%d), ana's logins admitted %.0f "
      "%% (%d/%d; target 100 %%) in p50 %.0f ms, max %.0f ms   [load %s]\n",
      attempts.load(), limited.load(), info_ms.size(), percentile(info_ms, 0.5),
      percentile(info_ms, 0.99),
      info_ms.empty() ? 0 : *std::max_element(info_ms.begin(), info_ms.end()), guests.percent(),
      guests.admitted.load(), guests.tried.load(), logins.percent(), logins.admitted.load(),
      logins.tried.load(), percentile(login_ms, 0.5),
      login_ms.empty() ? 0 : *std::max_element(login_ms.begin(), login_ms.end()),
      load_average().c_str());
}

void session_flood(const std::string& flipper) {
  Server s(flipper, {});
  add_ana(s, flipper);
  const std::string ana = login_cookie(
      http_once(s.port, "127.0.0.1", "POST", "/api/v1/login", login_body(kAnaPassword)));
  std::atomic<bool> stop{false};
  std::atomic<long> opened{0}, refused{0};
  std::vector<std::thread> attackers;
  attackers.reserve(40);
  for (int a = 0; a < 40; ++a)
    attackers.emplace_back([&, a] {
      while (!stop) {
        const Answer r =
            http_once(s.port, address(40, a), "POST", "/api/v1/request", R"({"op":"state"})");
        ++(r.status == 200 ? opened : refused);
      }
    });
  Rate guests, users;
  std::vector<std::thread> probes;
  probes.push_back(every(250ms, stop, [&](int i) {
    ++guests.tried;
    guests.admitted +=
        http_once(s.port, address(50, i), "POST", "/api/v1/request", R"({"op":"state"})").status ==
        200;
  }));
  probes.push_back(every(250ms, stop, [&](int) {
    ++users.tried;
    users.admitted += http_once(s.port, "127.0.0.1", "POST", "/api/v1/request", R"({"op":"state"})",
                                "Cookie: " + ana + "\r\n")
                          .status == 200;
  }));
  std::this_thread::sleep_for(kAttack);
  stop = true;
  for (auto& t : attackers) t.join();
  for (auto& t : probes) t.join();
  std::printf(
      "session   40 addresses flood new guest sessions for 10 s (%ld opened, %ld refused): new "
      "sessions of a logged-in user admitted %.0f %% (%d/%d; target 100 %%), new guests from "
      "fresh addresses admitted %.0f %% (%d/%d)   [load %s]\n",
      opened.load(), refused.load(), users.percent(), users.admitted.load(), users.tried.load(),
      guests.percent(), guests.admitted.load(), guests.tried.load(), load_average().c_str());
}

}  // namespace flipper::bench::serve

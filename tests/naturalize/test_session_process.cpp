// `flipper session` processes over one lexicon file: rules come back in a new process, and a
// session killed with SIGKILL at random moments never loses a definition it answered.
#include <poll.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <random>
#include <set>
#include <thread>

#include "flipper/kernel/lexicon_store.hpp"
#include "naturalize_fixture.hpp"

using namespace flipper::naturalizetest;
using flipper::kernel::Json;

namespace {

const std::string kFlipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";

/// `flipper session` with piped stdin/stdout.
class Session {
 public:
  explicit Session(const std::string& store) {
    int in[2], out[2];
    REQUIRE(pipe(in) == 0);
    REQUIRE(pipe(out) == 0);
    pid_ = fork();
    REQUIRE(pid_ >= 0);
    if (pid_ == 0) {
      dup2(in[0], 0);
      dup2(out[1], 1);
      close(in[1]);
      close(out[0]);
      const std::string set = "lexicon.path=" + store;
      execl(kFlipper.c_str(), kFlipper.c_str(), "session", "--set", set.c_str(), "-",
            static_cast<char*>(nullptr));
      _exit(127);
    }
    close(in[0]);
    close(out[1]);
    to_ = in[1];
    from_ = out[0];
    signal(SIGPIPE, SIG_IGN);
  }
  ~Session() {
    close(to_);
    close(from_);
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  void kill_now() {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  /// Sends a request; returns its answer, or null when the process died first.
  Json ask(const Json& request) {
    const std::string line = request.dump() + "\n";
    if (::write(to_, line.data(), line.size()) != static_cast<ssize_t>(line.size())) return nullptr;
    for (;;) {
      if (auto nl = buffer_.find('\n'); nl != std::string::npos) {
        std::string answer = buffer_.substr(0, nl);
        buffer_.erase(0, nl + 1);
        return Json::parse(answer);
      }
      pollfd p{from_, POLLIN, 0};
      if (poll(&p, 1, 60000) <= 0) return nullptr;
      char buf[4096];
      const ssize_t n = ::read(from_, buf, sizeof buf);
      if (n <= 0) return nullptr;
      buffer_.append(buf, static_cast<std::size_t>(n));
    }
  }

 private:
  pid_t pid_ = -1;
  int to_ = -1, from_ = -1;
  std::string buffer_;
};

std::string integrity(const std::string& path) {
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) == SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  REQUIRE(sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr) == SQLITE_OK);
  REQUIRE(sqlite3_step(st) == SQLITE_ROW);
  std::string result = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
  sqlite3_finalize(st);
  sqlite3_close(db);
  return result;
}

/// A head no core rule reads: "zork" + letters of n.
std::string head_for(long n) {
  std::string w = "zork";
  do {
    w += static_cast<char>('a' + n % 26);
    n /= 26;
  } while (n > 0);
  return w + " left";
}

}  // namespace

TEST_CASE("a new flipper session process gets the rules and weights back",
          "[naturalize][process]") {
  const std::string store = scratch("proc") + ".sqlite";
  {
    Session s(store);
    REQUIRE(s.ask({{"op", "user"}, {"name", "ana"}})["ok"] == true);
    REQUIRE(s.ask({{"op", "define"},
                   {"head", "pick 3 items"},
                   {"body", {"repeat 3 times pick item"}}})["ok"] == true);
    REQUIRE(s.ask({{"op", "query"}, {"text", "drop 2 items"}})["status"] == "induced");
    REQUIRE(s.ask({{"op", "accept"}, {"rank", 0}})["ok"] == true);
  }
  Session s(store);
  REQUIRE(s.ask({{"op", "user"}, {"name", "bob"}})["ok"] == true);
  const Json q = s.ask({{"op", "query"}, {"text", "drop 2 items"}});
  CHECK(q["status"] == "induced");
  CHECK(q["candidates"][0]["formula"] == "{repeat 2 times {drop item }}");
  int uses = 0;
  const Json listed = s.ask({{"op", "rules"}});
  INFO(listed.dump());
  for (const auto& r : listed["rules"]) uses += r["uses_by_author"].get<int>();
  CHECK(uses == 1);
  flipper::kernel::LexiconStore reopened(store);
  CHECK(reopened.load_weights("global").has_value());
}

TEST_CASE("SIGKILL of flipper session loses no answered definition",
          "[naturalize][process][kill]") {
  const std::string store = scratch("kill") + ".sqlite";
  std::mt19937 rng(7);
  std::set<std::string> answered;
  long next = 0;
  int kills_mid_stream = 0;
  for (int round = 0; round < 30; ++round) {
    {
      Session s(store);
      REQUIRE(s.ask({{"op", "user"}, {"name", "ana"}})["ok"] == true);  // started up
      const int after_ms = std::uniform_int_distribution<int>(1, 60)(rng);
      std::thread killer([&s, after_ms] {
        std::this_thread::sleep_for(std::chrono::milliseconds(after_ms));
        s.kill_now();
      });
      for (;; ++next) {
        const std::string head = head_for(next);
        const Json a = s.ask({{"op", "define"}, {"head", head}, {"body", {"move left"}}});
        if (a.is_null()) break;  // killed
        REQUIRE(a["ok"] == true);
        answered.insert(head);
      }
      killer.join();
      ++next;
      ++kills_mid_stream;
    }
    REQUIRE(integrity(store) == "ok");
    flipper::kernel::LexiconStore reopened(store);
    std::set<std::string> heads;
    for (const auto& d : reopened.definitions()) heads.insert(d.head);
    for (const auto& h : answered) {
      INFO("round " << round << ": answered definition '" << h << "'");
      REQUIRE(heads.count(h) == 1);
    }
  }
  CHECK(kills_mid_stream == 30);
  CHECK(answered.size() >= 30);
}

// `flipper session` processes over one lexicon file: rules come back in a new process, a rule or
// deletion acknowledged in one process is seen by the others before their next parse, and a
// session killed with SIGKILL at random moments never loses a definition it answered.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <set>
#include <thread>

#include "child_process.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "naturalize_fixture.hpp"
#include "sqlite_integrity.hpp"

using namespace flipper::naturalizetest;
using flipper::kernel::Json;

namespace {

const std::string kFlipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";

/// `flipper session` on one lexicon file, driven request by request.
class Session {
 public:
  /// `sets`: more `--set` values (e.g. another scorer).
  explicit Session(const std::string& store, const std::vector<std::string>& sets = {})
      : child_(args(store, sets)) {}
  void kill_now() { child_.kill_now(); }
  /// Sends a request; returns its answer, or null when the process died first.
  Json ask(const Json& request) {
    if (!child_.write_line(request.dump())) return nullptr;
    const std::string answer = child_.read_line(std::chrono::seconds(60));
    return answer.empty() ? Json(nullptr) : Json::parse(answer);
  }

 private:
  static std::vector<std::string> args(const std::string& store,
                                       const std::vector<std::string>& sets) {
    std::vector<std::string> a{kFlipper, "session", "--set", "lexicon.path=" + store};
    for (const auto& set : sets) a.insert(a.end(), {"--set", set});
    a.push_back("-");
    return a;
  }
  flipper::testsupport::ChildProcess child_;
};

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
  const std::string store = scratch_path("proc") + ".sqlite";
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
  // The loglinear scorer is incremental: its weights are stored as sums, never as a whole state.
  flipper::naturalization::LexiconStore reopened(store);
  CHECK_FALSE(reopened.load_weights("global").has_value());
}

namespace {

using Weights = std::map<std::pair<std::string, std::string>, std::pair<double, double>>;

Weights stored_weights(const std::string& store) {
  Weights w;
  flipper::naturalization::LexiconStore s(store);
  for (const auto& c : s.weight_changes("global")) w[{c.model, c.feature}] = {c.weight, c.aux};
  return w;
}

// One user's learning step, in two halves: a query with two readings, then the given one
// accepted.
void ask_two_readings(Session& s, const std::string& name) {
  REQUIRE(s.ask({{"op", "user"}, {"name", name}})["ok"] == true);
  const Json q = s.ask({{"op", "query"}, {"text", "pick item not is red and is green"}});
  REQUIRE(q["candidates"].size() >= 2);
}
void accept(Session& s, int rank) {
  REQUIRE(s.ask({{"op", "accept"}, {"rank", rank}})["ok"] == true);
}
void learn(Session& s, const std::string& name, int rank) {
  ask_two_readings(s, name);
  accept(s, rank);
}

}  // namespace

TEST_CASE("two processes learning on one lexicon both keep their weight updates",
          "[naturalize][process][weights]") {
  // Each user's update alone, from the same (empty) weights, in a store of its own.
  const std::string only_ana = scratch_path("w-ana") + ".sqlite";
  const std::string only_bob = scratch_path("w-bob") + ".sqlite";
  {
    Session a(only_ana);
    learn(a, "ana", 1);
  }
  {
    Session b(only_bob);
    learn(b, "bob", 0);
  }
  const Weights ana = stored_weights(only_ana), bob = stored_weights(only_bob);
  REQUIRE_FALSE(ana.empty());
  REQUIRE_FALSE(bob.empty());
  // Both processes ask before either accepts: neither learns against the other's update (a
  // process picks up others' weights before it parses: docs/naturalization.md §5 "Learned
  // state"), so the store must hold the sum of the two updates (last-writer-wins would keep one).
  const std::string shared = scratch_path("w-both") + ".sqlite";
  {
    Session a(shared), b(shared);
    ask_two_readings(a, "ana");
    ask_two_readings(b, "bob");
    accept(a, 1);
    accept(b, 0);
  }
  Weights expected = ana;
  for (const auto& [k, v] : bob) {
    auto& e = expected[k];
    e = {e.first + v.first, e.second + v.second};
  }
  const Weights both = stored_weights(shared);
  CHECK(both == expected);
  // A third process starts from both updates.
  Session c(shared);
  learn(c, "cy", 1);
  const Weights after = stored_weights(shared);
  CHECK(after.size() >= both.size());
}

namespace {

const std::vector<std::string> kPerceptron{"scorer.plugin=perceptron"};
const std::string kTwoReadings = "pick item not is red and is green";

// The score a new perceptron process on `store` gives the reading `formula` of kTwoReadings.
double perceptron_score(const std::string& store, const std::string& formula) {
  Session s(store, kPerceptron);
  const Json q = s.ask({{"op", "query"}, {"text", kTwoReadings}});
  for (const auto& c : q["candidates"])
    if (c["formula"] == formula) return c["score"].get<double>();
  FAIL("no reading " << formula << " in " << q.dump());
  return 0;
}

}  // namespace

// The perceptron is incremental too (flipper/toolkit/linear_scorer.hpp): an accept stores the
// changes of its weights and of its accept counter as sums, so concurrent learners add up instead
// of the last whole-state save replacing the others'.
TEST_CASE("two perceptron processes learning on one lexicon both keep their updates",
          "[naturalize][process][weights]") {
  const std::string fresh = scratch_path("p-fresh") + ".sqlite";
  const std::string only_ana = scratch_path("p-ana") + ".sqlite";
  const std::string shared = scratch_path("p-both") + ".sqlite";
  std::string accepted;  // the reading ranked second by a fresh model, which both accept
  {
    Session a(only_ana, kPerceptron);
    REQUIRE(a.ask({{"op", "user"}, {"name", "ana"}})["ok"] == true);
    const Json q = a.ask({{"op", "query"}, {"text", kTwoReadings}});
    REQUIRE(q["candidates"].size() >= 2);
    accepted = q["candidates"][1]["formula"];
    REQUIRE(a.ask({{"op", "accept"}, {"rank", 1}})["ok"] == true);
  }
  {
    // Both started (an answer means the store and its weights are loaded) before either learns:
    // a process still starting when the other commits would load that update as its own start.
    // Both ask before either accepts (above): each learns from the same empty model.
    Session a(shared, kPerceptron), b(shared, kPerceptron);
    ask_two_readings(a, "ana");
    ask_two_readings(b, "bob");
    accept(a, 1);
    accept(b, 1);
  }
  // Ana's update alone: Δ = φ(accepted) − φ(predicted) on w and u (c = 1), one accept counted.
  const Weights ana = stored_weights(only_ana);
  REQUIRE(ana.count({"", "#accepts"}) == 1);
  CHECK(ana.at({"", "#accepts"}) == std::make_pair(1.0, 0.0));
  REQUIRE(ana.size() > 1);
  // Bob learnt the same update from the same (empty) model: the store holds twice each.
  Weights expected;
  for (const auto& [k, v] : ana) expected[k] = {2 * v.first, 2 * v.second};
  CHECK(stored_weights(shared) == expected);
  // A new process scores with both: averaged weights w − u/c = 2Δ − 2Δ/3 = 4Δ/3, against
  // Δ − Δ/2 = Δ/2 after ana's accept alone, so the accepted reading gains 8/3 as much.
  const double before = perceptron_score(fresh, accepted);
  const double after_ana = perceptron_score(only_ana, accepted);
  const double after_both = perceptron_score(shared, accepted);
  REQUIRE(after_ana > before);
  CHECK(after_both - before == Approx(8.0 / 3.0 * (after_ana - before)).epsilon(1e-9));
}

TEST_CASE("SIGKILL of flipper session loses no answered definition",
          "[naturalize][process][kill]") {
  const std::string store = scratch_path("kill") + ".sqlite";
  std::mt19937 rng(7);
  std::set<std::string> answered;
  long next = 0;
  int kills_mid_stream = 0;
  for (int round = 0; round < 30; ++round) {
    {
      Session s(store);
      REQUIRE(s.ask({{"op", "user"}, {"name", "ana"}})["ok"] == true);  // started up
      // The kill comes once this round has `after` answers (a condition, not a time: a slow or
      // busy machine kills at the same point of the stream), while the next define is on its way.
      const int after = std::uniform_int_distribution<int>(0, 12)(rng);
      std::mutex m;
      std::condition_variable cv;
      int in_round = 0;
      std::thread killer([&] {
        std::unique_lock lock(m);
        // Bound: 60 s for at most 12 defines (~2 ms each in Release).
        cv.wait_for(lock, std::chrono::seconds(60), [&] { return in_round >= after; });
        s.kill_now();
      });
      for (;; ++next) {
        const std::string head = head_for(next);
        const Json a = s.ask({{"op", "define"}, {"head", head}, {"body", {"move left"}}});
        if (a.is_null()) break;  // killed
        REQUIRE(a["ok"] == true);
        answered.insert(head);
        {
          std::lock_guard lock(m);
          ++in_round;
        }
        cv.notify_one();
      }
      killer.join();
      ++next;
      ++kills_mid_stream;
    }
    REQUIRE(flipper::testsupport::sqlite_integrity(store) == "ok");
    flipper::naturalization::LexiconStore reopened(store);
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

namespace {
std::uintmax_t file_size(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? static_cast<std::uintmax_t>(st.st_size) : 0;
}
}  // namespace

// WAL checkpoints run in a background thread of each process (sqlite_handle.hpp): kill a session
// right after an answered define, often while that thread copies pages into the database file.
TEST_CASE("SIGKILL right after an answered define, with background checkpoints, loses nothing",
          "[naturalize][process][kill]") {
  const std::string store = scratch_path("kill-checkpoint") + ".sqlite";
  std::mt19937 rng(11);
  std::set<std::string> answered;
  long next = 0;
  int checkpointed_rounds = 0;
  for (int round = 0; round < 6; ++round) {
    const std::uintmax_t size_before = file_size(store);
    {
      Session s(store);
      REQUIRE(s.ask({{"op", "user"}, {"name", "ana"}})["ok"] == true);
      // ~7 WAL pages per define: 150-250 defines cross the 1,000-page checkpoint mark.
      const int defines = std::uniform_int_distribution<int>(150, 250)(rng);
      for (int i = 0; i < defines; ++i, ++next) {
        const std::string head = head_for(next);
        const Json a = s.ask({{"op", "define"}, {"head", head}, {"body", {"move left"}}});
        REQUIRE(a["ok"] == true);
        answered.insert(head);
      }
      s.kill_now();  // right after the last answer
    }
    // Only a checkpoint writes the database file of a process that never closed it.
    if (file_size(store) > size_before) ++checkpointed_rounds;
    REQUIRE(flipper::testsupport::sqlite_integrity(store) == "ok");
    flipper::naturalization::LexiconStore reopened(store);
    std::set<std::string> heads;
    for (const auto& d : reopened.definitions()) heads.insert(d.head);
    for (const auto& h : answered) {
      INFO("round " << round << ": answered definition '" << h << "'");
      REQUIRE(heads.count(h) == 1);
    }
  }
  CHECK(checkpointed_rounds >= 4);  // the kills did land on processes that checkpointed
}

// Durability against power loss, which a kill cannot show: every answered define was preceded,
// in the answering thread, by an fdatasync of the WAL after the define's last write to it.
namespace {

struct SyncOrder {
  int answers = 0;         // defines answered ok
  int synced_answers = 0;  // ... each after a sync of the WAL it wrote in the answering thread
};

/// 40 defines through `flipper session` under strace at lexicon.durability `level`.
SyncOrder define_under_strace(const std::string& name, const std::string& level) {
  const std::string store = scratch_path(name) + ".sqlite";
  const std::string script = scratch_path(name) + ".jsonl";
  const std::string trace = scratch_path(name) + ".strace";
  {
    std::ofstream f(script);
    f << Json{{"op", "user"}, {"name", "ana"}}.dump() << "\n";
    for (long n = 0; n < 40; ++n)
      f << Json{{"op", "define"}, {"head", head_for(n)}, {"body", {"move left"}}}.dump() << "\n";
  }
  // LeakSanitizer cannot run under ptrace (the instrumented build's flipper would exit 1 at its
  // end); leaks are checked by every other run of it.
  const std::string cmd =
      "ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 strace -f -qq -y -s 40 "
      "-e trace=write,pwrite64,fdatasync,fsync -o '" +
      trace + "' " + kFlipper + " session --set lexicon.path=" + store +
      " --set lexicon.durability=" + level + " '" + script + "' > /dev/null 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);  // strace must be installed (tests/README)
  // "PID write(1</dev/null>, ..." / "PID pwrite64(4</x.sqlite-wal>, ..." / "PID fdatasync(4<..."
  const std::regex line_re(R"(^(\d+) +(\w+)\((\d+)<([^>]*)>)");
  // Per thread: wrote the WAL since its last answer / since its last WAL sync.
  std::map<std::string, bool> wrote, unsynced;
  int answers = 0, synced_answers = 0;
  std::ifstream in(trace);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, line_re)) continue;
    const std::string tid = m[1], call = m[2], fd = m[3], file = m[4];
    const bool wal = file.size() > 4 && file.compare(file.size() - 4, 4, "-wal") == 0;
    if (call == "pwrite64" && wal) wrote[tid] = unsynced[tid] = true;
    if ((call == "fdatasync" || call == "fsync") && wal) unsynced[tid] = false;
    if (call == "write" && fd == "1" &&
        line.find(R"({\"ok\":true,\"op\":\"define\")") != std::string::npos) {
      ++answers;
      if (wrote[tid] && !unsynced[tid]) ++synced_answers;
      wrote[tid] = false;
    }
  }
  return {answers, synced_answers};
}

}  // namespace

TEST_CASE("every answered define is synced to the WAL before its answer is written",
          "[naturalize][process][durability]") {
  const SyncOrder full = define_under_strace("sync-order", "full");  // the default level
  CHECK(full.answers == 40);
  CHECK(full.synced_answers == 40);
}

// lexicon.durability: normal (docs/naturalization.md §5): no sync on the answer's path, and still
// nothing answered is lost when the process is killed.
TEST_CASE("at lexicon.durability normal a define is answered unsynced and survives a kill",
          "[naturalize][process][durability]") {
  const SyncOrder normal = define_under_strace("sync-normal", "normal");
  CHECK(normal.answers == 40);
  CHECK(normal.synced_answers == 0);  // 40 small defines: no checkpoint, so no WAL sync at all
  const std::string store = scratch_path("kill-normal") + ".sqlite";
  std::set<std::string> answered;
  {
    Session s(store, {"lexicon.durability=normal"});
    REQUIRE(s.ask({{"op", "user"}, {"name", "ana"}})["ok"] == true);
    for (long n = 0; n < 10; ++n) {
      const Json a = s.ask({{"op", "define"}, {"head", head_for(n)}, {"body", {"move left"}}});
      REQUIRE(a["ok"] == true);
      answered.insert(head_for(n));
    }
    s.kill_now();  // SIGKILL right after the last answer: no close, no checkpoint
  }
  flipper::naturalization::LexiconStore reopened(store);
  std::set<std::string> heads;
  for (const auto& d : reopened.definitions()) heads.insert(d.head);
  CHECK(heads == answered);
}

TEST_CASE("a rule acknowledged in one process serves a running other one, and so does its deletion",
          "[naturalize][process][writers]") {
  const std::string store = scratch_path("two") + ".sqlite";
  Session a(store), b(store);
  REQUIRE(a.ask({{"op", "user"}, {"name", "ana"}})["ok"] == true);
  REQUIRE(b.ask({{"op", "user"}, {"name", "bob"}})["ok"] == true);
  CHECK(b.ask({{"op", "query"}, {"text", "glorp left"}})["status"] == "unparsable");
  const Json d = a.ask({{"op", "define"}, {"head", "glorp left"}, {"body", {"move left"}}});
  REQUIRE(d["ok"] == true);
  REQUIRE(d["rules"].size() == 1);
  const std::string id = d["rules"][0]["id"];
  const Json q = b.ask({{"op", "query"}, {"text", "glorp left"}});
  CHECK(q["status"] == "induced");  // acknowledged in a, usable in b at once
  CHECK(q["candidates"][0]["rules"] == Json::array({id}));
  CHECK(b.ask({{"op", "rules"}})["rules"].size() == 1);
  const Json refused = b.ask({{"op", "delete_rule"}, {"rule", id}});
  CHECK(refused["error"]["code"] == "forbidden");
  // b defines too: its id follows a's, assigned by the store (no per-process counter).
  const Json d2 = b.ask({{"op", "define"}, {"head", "glorq left"}, {"body", {"move left"}}});
  REQUIRE(d2["ok"] == true);
  CHECK(d2["rules"][0]["id"] != id);
  CHECK(a.ask({{"op", "query"}, {"text", "glorq left"}})["status"] == "induced");
  REQUIRE(a.ask({{"op", "delete_rule"}, {"rule", id}})["ok"] == true);
  CHECK(b.ask({{"op", "query"}, {"text", "glorp left"}})["status"] == "unparsable");
  CHECK(b.ask({{"op", "rules"}})["rules"].size() == 1);
}

// `flipper session` does not free its rules at exit (docs/naturalization.md §5 "Start-up at
// scale") but must still close the store: the last connection checkpoints the WAL into the
// database and removes it, as a process that tears everything down does.
TEST_CASE("flipper session closes the store at the end of its input though it keeps its rules",
          "[naturalize][process]") {
  const std::string store = scratch_path("exit") + ".sqlite";
  {
    flipper::testsupport::ChildProcess child(
        {kFlipper, "session", "--set", "lexicon.path=" + store, "-"});
    REQUIRE(child.write_line(R"({"op":"user","name":"ana"})"));
    REQUIRE(Json::parse(child.read_line())["ok"] == true);
    REQUIRE(child.write_line(
        R"({"op":"define","head":"pick 3 items","body":["repeat 3 times pick item"]})"));
    REQUIRE(Json::parse(child.read_line())["ok"] == true);
    struct stat st {};
    REQUIRE(stat((store + "-wal").c_str(), &st) == 0);  // the define is in the WAL
    CHECK(child.finish() == 0);
  }
  struct stat st {};
  CHECK(stat((store + "-wal").c_str(), &st) != 0);  // checkpointed and removed: closed
  CHECK(stat((store + "-shm").c_str(), &st) != 0);
  Session s(store);
  REQUIRE(s.ask({{"op", "user"}, {"name", "bob"}})["ok"] == true);
  CHECK(s.ask({{"op", "query"}, {"text", "drop 2 items"}})["candidates"][0]["formula"] ==
        "{repeat 2 times {drop item }}");
}

TEST_CASE("processes that create one new store at the same moment all start",
          "[naturalize][process][create]") {
  // Switching a new store to WAL needs it to itself, and SQLite answers the loser of that race
  // SQLITE_BUSY at once (no busy handler): the loser must look again and go on, not fail with
  // lexicon_busy. Each round starts six processes on a store that does not exist yet.
  int failed = 0;
  for (int round = 0; round < 30; ++round) {
    const std::string store = scratch_path("create-race") + ".sqlite";
    std::vector<std::unique_ptr<Session>> crowd;
    for (int i = 0; i < 6; ++i) crowd.push_back(std::make_unique<Session>(store));
    for (auto& s : crowd)
      if (s->ask({{"op", "user"}, {"name", "ana"}})["ok"] != true) ++failed;
  }
  CHECK(failed == 0);
}

TEST_CASE("a running process ranks with the weights and counters another process committed",
          "[naturalize][process][weights]") {
  // b is running before a learns; its next query must rank exactly as a process started after
  // (docs/naturalization.md §5 "Learned state"): scores bit for bit, use counts alike.
  const std::string store = scratch_path("w-running") + ".sqlite";
  Session a(store), b(store);
  REQUIRE(a.ask({{"op", "user"}, {"name", "ana"}})["ok"] == true);
  REQUIRE(b.ask({{"op", "user"}, {"name", "bob"}})["ok"] == true);
  REQUIRE(
      a.ask({{"op", "define"}, {"head", "zig left"}, {"body", {"move left", "move left"}}})["ok"] ==
      true);
  learn(a, "ana", 1);
  REQUIRE(a.ask({{"op", "query"}, {"text", "zig left"}})["ok"] == true);
  accept(a, 0);
  Session c(store);
  REQUIRE(c.ask({{"op", "user"}, {"name", "bob"}})["ok"] == true);
  for (const Json& request : {Json{{"op", "query"}, {"text", "pick item not is red and is green"}},
                              Json{{"op", "rules"}}}) {
    Json running = b.ask(request), fresh = c.ask(request);
    running.erase("ms");
    fresh.erase("ms");
    CHECK(running.dump() == fresh.dump());
  }
}

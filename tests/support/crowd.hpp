#pragma once
// The crowd (docs/naturalization.md §5): N `flipper session` processes on ONE lexicon file, each
// user defining, querying, accepting and deleting at once. Shared by the crowd test
// (tests/naturalization/naturalize) and the crowd benchmark (bench/crowd). Free of Catch2; the
// store is checked with raw SQL, independently of the lexicon module.
//
// User k ("u<k>") runs `defines` rounds; round i:
//   define "<word k,i> left" := "move left"      -> acknowledged rules recorded
//   query its own head (must be induced), accept rank 0
//   query the head of another user's acknowledged definition (must be induced: shared mode makes
//   a rule usable by every process once acknowledged)
//   odd rounds: delete the first rule of this round's definition (must succeed)
//   try to delete another user's rule (must be refused with `forbidden`)
// Afterwards every acknowledged rule must be in the store, live unless its author deleted it, and
// every deleted rule must have been deleted by its author.
#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "sanitizer_build.hpp"

namespace flipper::testsupport {

struct CrowdOptions {
  std::string flipper;  ///< the flipper binary
  std::string store;    ///< lexicon file (created)
  int users = 10;
  int defines = 10;                     ///< rounds per user
  std::vector<std::string> extra_sets;  ///< more --set k=v for every session
  /// When >= 0, only users 0 .. early_users-1 start at once; the others start their process once
  /// some definition is acknowledged, so each of them opens a store that already has rules (how
  /// many processes start that way does not depend on how fast the first ones are).
  int early_users = -1;
};

struct CrowdReport {
  int users = 0;
  long acknowledged_defines = 0;
  long acknowledged_rules = 0;
  long lost = 0;             ///< acknowledged rules missing, replaced or wrongly deleted
  long errors = 0;           ///< ok:false answers a user would see (besides the forbidden probe)
  long cross_checks = 0;     ///< queries of another user's acknowledged head
  long cross_failures = 0;   ///< ... that did not parse through an induced rule
  long foreign_deletes = 0;  ///< delete of another user's rule that was not refused
  long wrong_deletions = 0;  ///< rules flagged deleted that their author did not delete
  std::string integrity;     ///< PRAGMA integrity_check
  double seconds = 0;        ///< wall time of the whole crowd
  std::vector<double> define_ms;           ///< client-side latency of every define
  std::vector<std::string> error_samples;  ///< first few error answers

  double percentile(double p) const {
    if (define_ms.empty()) return 0;
    std::vector<double> v = define_ms;
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
    return v[std::min(i, v.size() - 1)];
  }
};

namespace crowd_detail {

using Json = nlohmann::json;

/// A head word no core rule reads: "zork" + letters of n (distinct n, distinct words).
inline std::string word_for(long n) {
  std::string w = "zork";
  do {
    w += static_cast<char>('a' + n % 26);
    n /= 26;
  } while (n > 0);
  return w;
}

struct Ack {
  std::string user;
  std::string head;
  std::vector<std::string> rules;
  bool will_delete = false;
};

struct Shared {
  std::mutex mu;
  std::condition_variable first_ack;  ///< notified when acks gets its first entry
  std::vector<Ack> acks;
  std::set<std::string> deleted_by_author;  ///< rule ids whose author's delete was answered ok
  CrowdReport report;

  void error(const std::string& what) {
    std::lock_guard<std::mutex> lock(mu);
    ++report.errors;
    if (report.error_samples.size() < 8) report.error_samples.push_back(what);
  }
};

inline Json ask(ChildProcess& child, const Json& request) {
  if (!child.write_line(request.dump())) return nullptr;
  const std::string line = child.read_line(std::chrono::seconds(120));
  if (line.empty()) return nullptr;
  try {
    return Json::parse(line);
  } catch (const std::exception&) {
    return nullptr;
  }
}

inline bool ok(const Json& a) {
  return a.is_object() && a.value("ok", false);
}

inline std::string describe(const std::string& user, const Json& request, const Json& answer) {
  return user + ": " + request.dump() + " -> " + (answer.is_null() ? "(no answer)" : answer.dump());
}

inline void run_user(const CrowdOptions& o, int k, Shared& shared) {
  const std::string name = "u" + std::to_string(k);
  if (o.early_users >= 0 && k >= o.early_users) {
    std::unique_lock<std::mutex> lock(shared.mu);
    // Bounded: with no definition acknowledged in 300 s the late users start anyway, and the
    // test's own checks report what went wrong.
    shared.first_ack.wait_for(lock, std::chrono::seconds(300),
                              [&shared] { return !shared.acks.empty(); });
  }
  std::vector<std::string> args = {o.flipper, "session", "--set", "lexicon.path=" + o.store};
  if (kAddressSanitizer) {
    // Instrumented, the crowd's 100-200 processes run without LeakSanitizer's exit check: in CI
    // one of them once lost its leak check to LSan's own crash ("Tracer caught signal 11" while
    // it stopped the threads to scan them), a fault of the sanitizer runtime, not of this
    // process, and the crowd's guarantees are about the store. The session process's leaks are
    // checked by every other instrumented test that runs it (docs/testing.md, "Fuzzing and
    // sanitizers").
    const char* asan = std::getenv("ASAN_OPTIONS");
    std::string options = asan != nullptr && *asan != '\0' ? std::string(asan) + ":" : "";
    args.insert(args.begin(), {"/usr/bin/env", "ASAN_OPTIONS=" + options + "detect_leaks=0"});
  }
  for (const auto& s : o.extra_sets) {
    args.push_back("--set");
    args.push_back(s);
  }
  args.push_back("-");
  ChildProcess child(args);
  std::mt19937 rng(static_cast<unsigned>(k) * 7919u + 1u);
  auto checked = [&](const Json& request) {
    Json a = ask(child, request);
    if (!ok(a)) shared.error(describe(name, request, a));
    return a;
  };
  checked({{"op", "user"}, {"name", name}});
  for (int i = 0; i < o.defines; ++i) {
    const std::string head = word_for(static_cast<long>(k) * 100000 + i) + " left";
    const Json def = {{"op", "define"}, {"head", head}, {"body", {"move left"}}};
    const auto t0 = std::chrono::steady_clock::now();
    const Json a = checked(def);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    Ack ack{name, head, {}, i % 2 == 1};
    if (ok(a))
      for (const auto& r : a["rules"]) ack.rules.push_back(r.value("id", std::string()));
    {
      std::lock_guard<std::mutex> lock(shared.mu);
      shared.report.define_ms.push_back(ms);
      if (ok(a)) {
        ++shared.report.acknowledged_defines;
        shared.report.acknowledged_rules += static_cast<long>(ack.rules.size());
        shared.acks.push_back(ack);
        shared.first_ack.notify_all();
      }
    }
    if (!ok(a) || ack.rules.empty()) continue;

    const Json own = checked({{"op", "query"}, {"text", head}});
    if (ok(own) && own.value("status", "") != "induced")
      shared.error(describe(name, {{"op", "query"}, {"text", head}}, own));
    if (ok(own) && !own["candidates"].empty()) checked({{"op", "accept"}, {"rank", 0}});

    // Another user's acknowledged definition that stays: usable here now.
    Ack other;
    {
      std::lock_guard<std::mutex> lock(shared.mu);
      std::vector<const Ack*> pool;
      for (const auto& x : shared.acks)
        if (x.user != name && !x.will_delete) pool.push_back(&x);
      if (!pool.empty()) other = *pool[rng() % pool.size()];
    }
    if (!other.user.empty()) {
      const Json q = {{"op", "query"}, {"text", other.head}};
      const Json a2 = checked(q);
      std::lock_guard<std::mutex> lock(shared.mu);
      ++shared.report.cross_checks;
      if (ok(a2) && a2.value("status", "") != "induced") ++shared.report.cross_failures;
    }

    if (ack.will_delete) {
      const Json d = checked({{"op", "delete_rule"}, {"rule", ack.rules.front()}});
      if (ok(d)) {
        std::lock_guard<std::mutex> lock(shared.mu);
        shared.deleted_by_author.insert(name + "\x1f" + ack.rules.front());
      }
    }
    if (!other.user.empty()) {
      const Json d = ask(child, {{"op", "delete_rule"}, {"rule", other.rules.front()}});
      const std::string code =
          d.is_object() && d.contains("error") ? d["error"].value("code", "") : "";
      if (ok(d)) {
        std::lock_guard<std::mutex> lock(shared.mu);
        ++shared.report.foreign_deletes;
      } else if (code != "forbidden") {
        shared.error(describe(name, {{"op", "delete_rule"}, {"rule", other.rules.front()}}, d));
      }
    }
  }
  if (child.finish() != 0) shared.error(name + ": flipper session did not exit with 0");
}

struct StoredRow {
  std::string author;
  std::string head;
  bool deleted = false;
};

inline std::map<std::string, StoredRow> read_rules(const std::string& path,
                                                   std::string& integrity) {
  std::map<std::string, StoredRow> rows;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    integrity = "cannot open";
    sqlite3_close(db);
    return rows;
  }
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr) == SQLITE_OK &&
      sqlite3_step(st) == SQLITE_ROW)
    integrity = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
  sqlite3_finalize(st);
  if (sqlite3_prepare_v2(db, "SELECT id, author, head, deleted FROM rules", -1, &st, nullptr) ==
      SQLITE_OK)
    while (sqlite3_step(st) == SQLITE_ROW)
      rows[reinterpret_cast<const char*>(sqlite3_column_text(st, 0))] = {
          reinterpret_cast<const char*>(sqlite3_column_text(st, 1)),
          reinterpret_cast<const char*>(sqlite3_column_text(st, 2)),
          sqlite3_column_int(st, 3) != 0};
  sqlite3_finalize(st);
  sqlite3_close(db);
  return rows;
}

}  // namespace crowd_detail

/// Runs the crowd and checks the store; never throws for what the sessions answer.
inline CrowdReport run_crowd(const CrowdOptions& o) {
  using namespace crowd_detail;
  Shared shared;
  shared.report.users = o.users;
  const auto t0 = std::chrono::steady_clock::now();
  {
    std::vector<std::thread> threads;
    for (int k = 0; k < o.users; ++k)
      threads.emplace_back([&o, k, &shared] { run_user(o, k, shared); });
    for (auto& t : threads) t.join();
  }
  CrowdReport r = std::move(shared.report);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto rows = read_rules(o.store, r.integrity);
  std::set<std::string> deleted_ids;
  for (const auto& ack : shared.acks)
    for (const auto& id : ack.rules) {
      auto it = rows.find(id);
      const bool deleted_by_author = shared.deleted_by_author.count(ack.user + "\x1f" + id) > 0;
      if (deleted_by_author) deleted_ids.insert(id);
      if (it == rows.end() || it->second.author != ack.user || it->second.head != ack.head ||
          it->second.deleted != deleted_by_author)
        ++r.lost;
    }
  for (const auto& [id, row] : rows)
    if (row.deleted && !deleted_ids.count(id)) ++r.wrong_deletions;
  return r;
}

}  // namespace flipper::testsupport

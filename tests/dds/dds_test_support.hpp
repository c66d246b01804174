#pragma once
// DDS test helpers: the loopback configuration (never a participant without it), this test
// process's own DDS domain (dds_domain.hpp: no other checkout's run can meet it), flipper
// children on that domain with their own lexicon, waiting for conditions, a test participant.
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "dds_domain.hpp"
#include "flipper/dds/cyclone_config.hpp"
#include "flipper/dds/participant.hpp"
#include "flipper/dds/transport.hpp"

namespace flipper::ddstest {

using nlohmann::json;

/// ctest sets CYCLONEDDS_URI to the loopback config; a direct run gets the same here.
inline void ensure_loopback_env() {
  const char* uri = std::getenv("CYCLONEDDS_URI");
  if (uri == nullptr || *uri == '\0') setenv("CYCLONEDDS_URI", dds::loopback_xml().c_str(), 1);
  const auto sel = dds::network_selection(
      dds::resolve_cyclone_config(std::getenv("CYCLONEDDS_URI"), "CYCLONEDDS_URI"), 0);
  REQUIRE(sel.interfaces == std::vector<std::string>{"lo"});
  REQUIRE(sel.unprovable.empty());
}

/// This test process's DDS domain (claimed for the life of the process).
inline int test_domain() {
  return testsupport::claimed_dds_domain();
}

/// A participant of the test itself on `domain`, loopback only.
inline std::shared_ptr<dds::Participant> test_participant(int domain) {
  ensure_loopback_env();
  dds::Transport t;
  t.xml = dds::loopback_xml();
  t.interfaces = {"lo"};
  t.source = "test";
  static std::ostringstream sink;
  return std::make_shared<dds::Participant>(domain, t, sink);
}

inline std::string flipper_bin() {
  return std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";
}

inline std::filesystem::path scratch_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() /
             ("flipper-dds-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Polls `ok` every 20 ms until it holds or `timeout` passes; returns whether it held.
inline bool wait_until(const std::function<bool()>& ok,
                       std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (ok()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return ok();
}

/// `flipper session` with lexicon replication: one site.
struct Site {
  std::string name;
  std::string store;
  std::vector<std::string> args;
  std::unique_ptr<testsupport::ChildProcess> child;

  Site(std::string site, const std::filesystem::path& dir, int domain,
       std::vector<std::string> extra = {})
      : name(std::move(site)), store((dir / (name + ".sqlite")).string()) {
    ensure_loopback_env();
    args = {flipper_bin(), "session",
            "--set",       "lexicon.replication=dds",
            "--set",       "lexicon.site=" + name,
            "--set",       "lexicon.path=" + store,
            "--set",       "dds.domain=" + std::to_string(domain),
            "--set",       "rewriter=null"};
    args.insert(args.end(), extra.begin(), extra.end());
    start();
  }
  void start() { child = std::make_unique<testsupport::ChildProcess>(args); }
  json call(const json& request) {
    REQUIRE(child->write_line(request.dump()));
    const std::string line = child->read_line(std::chrono::seconds(30));
    REQUIRE_FALSE(line.empty());
    return json::parse(line);
  }
  json rules() { return call({{"op", "rules"}})["rules"]; }
  /// The top formula for `text`, or "" when unparsable.
  std::string top(const std::string& text) {
    const json a = call({{"op", "query"}, {"text", text}});
    return a["candidates"].empty() ? "" : a["candidates"][0]["formula"].get<std::string>();
  }
};

inline std::set<std::string> rule_shapes(Site& site, const std::string& head = {}) {
  std::set<std::string> out;
  for (const auto& r : site.rules())
    if (head.empty() || r["head"] == head)
      out.insert(r["lhs"].get<std::string>() + " -> " + r["rhs"].dump() + " => " +
                 r["semantics"].get<std::string>());
  return out;
}

/// Definitions per head in a store, read through `flipper lexicon export`.
inline std::map<std::string, int> definitions_per_head(const std::string& store) {
  testsupport::ChildProcess p(
      {flipper_bin(), "lexicon", "export", "-", "--set", "lexicon.path=" + store});
  std::map<std::string, int> out;
  std::istringstream lines(p.read_all());
  for (std::string line; std::getline(lines, line);) {
    const json j = json::parse(line);
    if (j["type"] == "definition") ++out[j["head"].get<std::string>()];
  }
  REQUIRE(p.finish() == 0);
  return out;
}

}  // namespace flipper::ddstest

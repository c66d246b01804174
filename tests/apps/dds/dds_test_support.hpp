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
#include "flipper/dds/lexicon_replicator.hpp"
#include "flipper/dds/participant.hpp"
#include "flipper/dds/transport.hpp"
#include "flipper/msg/LexiconEvent.h"

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

/// The study world with the robot at (x, y), holding nothing.
inline json study_world_with_robot(int x, int y) {
  std::ifstream in(std::string(FLIPPER_SOURCE_DIR) + "/configs/worlds/study2018.json");
  json w = json::parse(in);
  w["robot"] = {{"x", x}, {"y", y}, {"holding", json::array()}};
  return w;
}

/// A transient-local, keep-all reader of T on `topic` (a late reader gets the latched sample).
template <class T>
struct SampleReader {
  dds_entity_t reader = 0;
  SampleReader(dds::Participant& p, const dds_topic_descriptor_t* desc, const std::string& topic) {
    dds::Qos qos;
    dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_durability(qos.q, DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_qset_history(qos.q, DDS_HISTORY_KEEP_ALL, DDS_LENGTH_UNLIMITED);
    reader = dds_create_reader(p.handle(), p.topic(desc, topic), qos.q, nullptr);
    REQUIRE(reader > 0);
  }
  ~SampleReader() { dds_delete(reader); }
  SampleReader(const SampleReader&) = delete;
  SampleReader& operator=(const SampleReader&) = delete;
  /// Calls `f` on every valid sample received so far; how many there were.
  int take(const std::function<void(const T&)>& f, int at_most = 1 << 30) {
    int got = 0;
    void* samples[1] = {nullptr};
    dds_sample_info_t info;
    while (got < at_most && dds_take(reader, samples, &info, 1, 1) > 0) {
      if (info.valid_data) {
        f(*static_cast<const T*>(samples[0]));
        ++got;
      }
      dds_return_loan(reader, samples, 1);
    }
    return got;
  }
  /// Calls `f` on the next valid sample within 10 s; false when none came.
  bool next(const std::function<void(const T&)>& f) {
    return wait_until([&] { return take(f, 1) == 1; }, std::chrono::seconds(10));
  }
};

/// A writer on the lexicon topic with the replication's QoS.
inline dds_entity_t lexicon_writer(dds::Participant& p) {
  dds::Qos qos;
  dds::history_qos(qos);
  const dds_entity_t w = dds_create_writer(
      p.handle(), p.topic(&flipper_msg_dds__LexiconEvent__desc, dds::kLexiconTopic), qos.q,
      nullptr);
  REQUIRE(w > 0);
  return w;
}

/// Writes `e` as it is (no check, no signature added): forged and malformed events included.
inline void write_event(dds_entity_t w, const dds::LexiconEvent& e) {
  const auto text = [](const std::string& str) { return const_cast<char*>(str.c_str()); };
  flipper_msg_dds__LexiconEvent_ s{};
  std::vector<char*> body;
  for (const auto& b : e.body) body.push_back(text(b));
  s.site_ = text(e.site);
  s.version_ = e.version;
  s.kind_ = text(e.kind);
  s.lamport_ = e.lamport;
  s.time_ = e.time;
  s.author_ = text(e.author);
  s.head_ = text(e.head);
  s.body_._buffer = body.data();
  s.body_._length = s.body_._maximum = static_cast<uint32_t>(body.size());
  s.world_ = text(e.world);
  s.target_site_ = text(e.target_site);
  s.target_version_ = e.target_version;
  s.target_rule_ = text(e.target_rule);
  s.certificate_ = text(e.certificate);
  s.signature_._buffer = reinterpret_cast<uint8_t*>(text(e.signature));
  s.signature_._length = s.signature_._maximum = static_cast<uint32_t>(e.signature.size());
  REQUIRE(dds_write(w, &s) == DDS_RETCODE_OK);
}

/// A command's exit status and what it printed (standard output and error together).
struct CommandRun {
  int status;
  std::string out;
};

/// Runs `args` through /bin/sh's exec, each one word (single-quoted), and collects its output.
inline CommandRun run_command(const std::vector<std::string>& args) {
  std::string command = "exec";
  for (const auto& a : args) command += " '" + a + "'";
  testsupport::ChildProcess p({"/bin/sh", "-c", command + " 2>&1"});
  std::string out = p.read_all();
  return {p.finish(), std::move(out)};
}

/// `flipper dds security ARGS...`.
inline CommandRun security_command(std::vector<std::string> args) {
  args.insert(args.begin(), {flipper_bin(), "dds", "security"});
  return run_command(args);
}

/// What a shell command prints (the openssl command line: the independent reader).
inline std::string shell_output(const std::string& command) {
  return run_command({"/bin/sh", "-c", command}).out;
}

/// A file's bytes ("" when it cannot be read).
inline std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace flipper::ddstest

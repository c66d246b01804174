// A real network, on one machine (docs/ros2.md, "Across a network"): two hosts, network
// namespaces joined by a veth pair (veth_hosts.sh makes them and runs this test on host A), each
// with its own address, DDS Security on, discovery through the unicast peers only (multicast is
// off in the Cyclone configuration and on both ends of the pair), both hosts behind the firewall
// the document gives (nft, when installed). A phrase defined at site lab1
// on host A is used at site lab2 on host B; a robot's plan made on host B reaches an operator on
// host A; every `flipper dds` exits within its stated bound on SIGTERM there too. The
// replication time across the pair (define answered at lab1 -> the rule parses at lab2) is
// printed, the median of several definitions.
//
// Nothing here can touch the machine's real network: this process and every node it starts run
// in the two private network namespaces, whose only interfaces are their `lo` and their end of
// the pair (veth_hosts.sh).
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string_view>

#include "dds_session_ends.hpp"
#include "dds_test_support.hpp"
#include "flipper/dds/keystore.hpp"
#include "flipper/dds/names.hpp"
#include "flipper/msg/SessionLine.h"
#include "nav_msgs/msg/Path.h"

using namespace flipper;
using namespace flipper::ddstest;
using Clock = std::chrono::steady_clock;

namespace {

// The two hosts as veth_hosts.sh makes them.
struct Host {
  const char* interface;
  const char* address;
};
constexpr Host kHostA{"veth_a", "10.77.0.1"};
constexpr Host kHostB{"veth_b", "10.77.0.2"};

// docs/ros2.md, "Stopping": from SIGTERM to the exit.
constexpr std::chrono::milliseconds kStopBound{2000};
// Bounds for discovery with the security handshake (about a second) and for one answer; they
// only stop a run whose network is broken.
constexpr std::chrono::seconds kDiscovery{30};
constexpr std::chrono::seconds kAnswer{20};

// Cyclone's configuration on `self`: exactly its veth interface, no multicast, both hosts'
// addresses as unicast discovery peers (each host's own address too: its other participants
// are found there).
std::string cyclone_xml(const Host& self) {
  return std::string(
             "<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface "
             "name=\"") +
         self.interface +
         "\"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>"
         "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>20"
         "</MaxAutoParticipantIndex><Peers><Peer address=\"" +
         kHostA.address + "\"/><Peer address=\"" + kHostB.address +
         "\"/></Peers></Discovery></Domain></CycloneDDS>";
}

// The settings that put a flipper node on `self`'s network.
std::vector<std::string> network(const Host& self) {
  return {"--set", std::string("dds.interfaces=[") + self.interface + "]", "--set",
          "dds.config=" + cyclone_xml(self)};
}

// Host B's network namespace, as veth_hosts.sh hands it over (empty when not run through it).
std::string host_b_pid() {
  const char* pid = std::getenv("FLIPPER_VETH_HOST_B");
  return pid == nullptr ? "" : pid;
}

// The firewall of docs/ros2.md ("Across a network"), those very nft commands, on `self` for
// `domain`'s ports with MaxAutoParticipantIndex 20 (7410 + 250 d to 7451 + 250 d): the peers'
// discovery and data reach them through `self`'s interface, everything else to them is dropped.
// False with nft's message when nft is not installed or refuses.
bool firewall(const Host& self, int domain, std::string* out) {
  const int low = 7400 + 250 * domain + 10, high = low + 41;
  const std::string ports = std::to_string(low) + "-" + std::to_string(high);
  const std::string script =
      std::string("exec 2>&1\nset -e\n") +
      "nft add table inet flipper_dds\n"
      "nft add chain inet flipper_dds input '{ type filter hook input priority 0; policy accept; "
      "}'\n"
      "nft add rule inet flipper_dds input iifname lo accept\n"
      "nft add rule inet flipper_dds input iifname " +
      self.interface + " ip saddr '{ " + kHostA.address + ", " + kHostB.address + " }' udp dport " +
      ports + " accept\n" + "nft add rule inet flipper_dds input udp dport " + ports + " drop\n";
  std::vector<std::string> args = {"/bin/sh", "-c", script};
  if (std::string_view(self.interface) == kHostB.interface)
    args.insert(args.begin(),
                {std::getenv("FLIPPER_VETH_NSENTER"), "-t", host_b_pid(), "-n", "--"});
  testsupport::ChildProcess p(args);
  *out = p.read_all();
  return p.finish() == 0;
}

// `flipper dds ARGS...` on host A, or on host B through nsenter; stderr into `log`.
struct Node {
  pid_t pid = -1;
  std::string log;
  Node(const Host& host, std::vector<std::string> args, std::string log_file)
      : log(std::move(log_file)) {
    args.insert(args.begin(), {flipper_bin(), "dds"});
    if (std::string_view(host.interface) == kHostB.interface)
      args.insert(args.begin(),
                  {std::getenv("FLIPPER_VETH_NSENTER"), "-t", host_b_pid(), "-n", "--"});
    const auto more = network(host);
    args.insert(args.end(), more.begin(), more.end());
    std::vector<char*> argv;  // built before fork: the child calls only async-signal-safe code
    argv.reserve(args.size() + 1);
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      if (fd < 0 || dup2(fd, STDERR_FILENO) < 0) _exit(126);
      execv(argv[0], argv.data());
      _exit(127);
    }
  }
  std::string text() const { return file_text(log); }
  bool serving() const {
    return wait_until([&] { return text().find("serving") != std::string::npos; }, kDiscovery);
  }
  // SIGTERM, then the exit status (-1 for none) and the time to the exit.
  std::pair<int, std::chrono::milliseconds> stop() {
    const auto start = Clock::now();
    kill(pid, SIGTERM);
    int status = 0;
    const bool exited =
        wait_until([&] { return waitpid(pid, &status, WNOHANG) == pid; }, std::chrono::seconds(10));
    const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start);
    if (!exited) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
    }
    pid = -1;
    return {exited && WIFEXITED(status) ? WEXITSTATUS(status) : -1, took};
  }
  ~Node() {
    if (pid > 0) stop();
  }
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;
};

// The operator's requester of namespace `ns`: one session, one request at a time.
struct Client {
  dds_entity_t writer = 0, reader = 0, waitset = 0;
  std::uint64_t next_id = 1;
  Client(dds::Participant& p, const std::string& ns) {
    const SessionEnds ends = session_ends(p, ns);
    writer = ends.writer;
    reader = ends.reader;
    waitset = dds_create_waitset(p.handle());
    REQUIRE(waitset > 0);
    REQUIRE(dds_waitset_attach(waitset, dds_create_readcondition(reader, DDS_ANY_STATE), 0) == 0);
  }
  bool matched() {
    return wait_until(
        [&] {
          dds_publication_matched_status_t st;
          dds_subscription_matched_status_t sr;
          return dds_get_publication_matched_status(writer, &st) == 0 && st.current_count > 0 &&
                 dds_get_subscription_matched_status(reader, &sr) == 0 && sr.current_count > 0;
        },
        kDiscovery);
  }
  // The answer to `request` (null when none came within kAnswer).
  json call(const json& request) {
    const std::uint64_t id = next_id++;
    const std::string line = request.dump();
    send_line(writer, "veth", id, line);
    // Woken by the answer's arrival (a waitset), not by polling, so round trips are measured as
    // they are.
    json answer;
    const auto end = Clock::now() + kAnswer;
    while (answer.is_null() && Clock::now() < end) {
      void* samples[1] = {nullptr};
      dds_sample_info_t info;
      while (answer.is_null() && dds_take(reader, samples, &info, 1, 1) > 0) {
        const auto* a = static_cast<const flipper_msg_dds__SessionLine_*>(samples[0]);
        if (info.valid_data && a->request_id_ == id) answer = json::parse(a->line_);
        dds_return_loan(reader, samples, 1);
      }
      if (answer.is_null()) dds_waitset_wait(waitset, nullptr, 0, DDS_MSECS(100));
    }
    return answer;
  }
  // The top formula for `text`, "" when unparsable.
  std::string top(const std::string& text) {
    const json a = call({{"op", "query"}, {"text", text}});
    REQUIRE(a.is_object());
    return a["candidates"].empty() ? "" : a["candidates"][0]["formula"].get<std::string>();
  }
};

// The i-th of the words bab, bac, ..., zuz: no word of the core language, none a number.
std::string made_up_word(int i) {
  static const std::string consonants = "bcdfghjklmnpqrstvwxz", vowels = "aeiou";
  const auto c = consonants.size(), v = vowels.size();
  const auto n = static_cast<std::size_t>(i);
  return {consonants[n / (v * c) % c], vowels[n / c % v], consonants[n % c]};
}

// The network namespace of process `pid` ("net:[inode]").
std::string net_namespace(pid_t pid) {
  std::error_code ec;
  return std::filesystem::read_symlink("/proc/" + std::to_string(pid) + "/ns/net", ec).string();
}

// The nearest-rank percentile `p` (0 < p <= 1) of `v`.
double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

}  // namespace

TEST_CASE("two hosts on a veth pair: a phrase defined on one is used on the other, a plan crosses",
          "[dds][veth][security]") {
  INFO("run through tests/apps/dds/veth_hosts.sh (ctest does), which makes the two hosts");
  REQUIRE_FALSE(host_b_pid().empty());
  REQUIRE(std::getenv("FLIPPER_VETH_NSENTER") != nullptr);
  const int domain = test_domain();
  const auto dir = scratch_dir("veth");
  const std::string ks = (dir / "ks").string();
  REQUIRE(security_command({"init", ks}).status == 0);
  for (const std::vector<std::string>& add : {std::vector<std::string>{"lab1"},
                                              {"lab2"},
                                              {"robot1", "--role", "robot"},
                                              {"op", "--role", "operator", "--namespace", "lab1",
                                               "--namespace", "lab2", "--namespace", "robot1"}}) {
    std::vector<std::string> args = {"add", ks};
    args.insert(args.end(), add.begin(), add.end());
    REQUIRE(security_command(args).status == 0);
  }
  // Both hosts behind the documented firewall (when nft is there: scripts/packages-test.txt).
  // A kernel without nf_tables (some containers) refuses the first table: the hosts then run
  // without the firewall and say so; once host A has it, host B must take it too.
  if (run_command({"/bin/sh", "-c", "command -v nft"}).status == 0) {
    std::string out;
    if (firewall(kHostA, domain, &out)) {
      const bool set = firewall(kHostB, domain, &out);
      INFO(out);
      REQUIRE(set);
    } else {
      std::cout << "test_dds_veth: nft refused the firewall of docs/ros2.md, the hosts run "
                   "without it: "
                << out << std::endl;
    }
  } else {
    std::cout << "test_dds_veth: nft is not installed: the hosts run without the firewall of "
                 "docs/ros2.md"
              << std::endl;
  }
  const auto common = [&](const std::string& name) {
    return std::vector<std::string>{"--set", "dds.domain=" + std::to_string(domain),
                                    "--set", "dds.namespace=" + name,
                                    "--set", "dds.security.keystore=" + ks,
                                    "--set", "lexicon.path=" + (dir / (name + ".sqlite")).string(),
                                    "--set", "rewriter=null"};
  };
  const auto site = [&](const std::string& name) {
    auto args = common(name);
    args.insert(args.end(), {"--set", "lexicon.replication=dds", "--set", "lexicon.site=" + name});
    return args;
  };
  auto robot_args = common("robot1");
  robot_args.insert(robot_args.end(), {"--set", "publish.plans=dds"});

  // Site lab1 on host A; site lab2 and robot robot1 on host B.
  std::vector<std::unique_ptr<Node>> nodes;
  nodes.push_back(std::make_unique<Node>(kHostA, site("lab1"), (dir / "lab1.log").string()));
  nodes.push_back(std::make_unique<Node>(kHostB, site("lab2"), (dir / "lab2.log").string()));
  nodes.push_back(std::make_unique<Node>(kHostB, robot_args, (dir / "robot1.log").string()));
  Node &lab1 = *nodes[0], &lab2 = *nodes[1], &robot1 = *nodes[2];
  for (const auto& [node, host] : {std::pair{&lab1, kHostA}, {&lab2, kHostB}, {&robot1, kHostB}}) {
    INFO(node->text());
    REQUIRE(node->serving());
    const std::string log = node->text();
    CHECK(log.find(std::string("interfaces ") + host.interface + " (NOT loopback") !=
          std::string::npos);
    CHECK(log.find("DDS Security on") != std::string::npos);
    // Two hosts indeed: host B's nodes in another network namespace than this test's, lab1 in
    // this test's (host A's).
    const bool on_a = std::string_view(host.interface) == kHostA.interface;
    const std::string ns = net_namespace(node->pid);
    CHECK(ns.rfind("net:[", 0) == 0);
    CHECK((ns == net_namespace(::getpid())) == on_a);
  }

  // The operator, on host A: requests to the three namespaces, robot1's plans.
  dds::Transport transport;
  transport.xml = cyclone_xml(kHostA);
  transport.interfaces = {kHostA.interface};
  transport.loopback_only = false;
  transport.source = "test_dds_veth";
  std::ostringstream sink;
  dds::Participant op(domain, transport, sink, dds::security_properties(dds::Keystore{ks}, "op"));
  Client to_lab1(op, "lab1"), to_lab2(op, "lab2"), to_robot1(op, "robot1");
  SampleReader<nav_msgs_msg_dds__Path_> plans(op, &nav_msgs_msg_dds__Path__desc,
                                              dds::node_topic("robot1", "plan"));
  for (Client* c : {&to_lab1, &to_lab2, &to_robot1}) {
    INFO(lab1.text() << lab2.text() << robot1.text());
    REQUIRE(c->matched());
  }
  REQUIRE(to_lab1.call({{"op", "user"}, {"name", "ana"}})["ok"] == true);

  // Define at lab1 (host A), then ask lab2 (host B) until its answer uses the rule, back to back.
  // Returns the milliseconds from lab1's answer (the definition committed there) to the first
  // answer of lab2 that parses `use` as `expected`; -1 when it never did within kDiscovery.
  const auto replicate = [&](const std::string& head, const std::string& body,
                             const std::string& use, const std::string& expected) {
    INFO(head << " -> " << use);
    CHECK(to_lab2.top(use).empty());  // lab2 cannot parse it before
    const json defined = to_lab1.call({{"op", "define"}, {"head", head}, {"body", {body}}});
    REQUIRE(defined["ok"] == true);
    // Each query waits for its answer (one round trip across the pair), so the next one follows
    // at once: the time is known to within one round trip.
    const auto t0 = Clock::now();
    bool arrived = false;
    while (!arrived && Clock::now() < t0 + kDiscovery) arrived = to_lab2.top(use) == expected;
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    CHECK(arrived);
    return arrived ? ms : -1.0;
  };
  std::vector<double> times;
  // The generalized rule: "pick 3 items" defined, "drop 2 items" used.
  times.push_back(replicate("pick 3 items", "repeat 3 times pick item", "drop 2 items",
                            "{repeat 2 times {drop item }}"));
  // Then one-line definitions of new words ("veth bab" -> move left, ...): 7 here, as many as
  // FLIPPER_VETH_DEFINITIONS says for the benchmark (scripts/bench dds).
  const char* asked = std::getenv("FLIPPER_VETH_DEFINITIONS");
  const int words = asked != nullptr ? std::clamp(std::atoi(asked), 1, 500) : 7;
  const std::array<const char*, 4> bodies = {"move left", "move right", "move up", "move down"};
  for (int i = 0; i < words; ++i) {
    const std::string word = "veth " + made_up_word(i),
                      body = bodies.at(static_cast<std::size_t>(i) % bodies.size());
    times.push_back(replicate(word, body, word, "{" + body + "}"));
  }
  // For scale: a query's round trip across the pair (operator on A -> lab2 on B -> back).
  std::vector<double> round_trips;
  for (int i = 0; i < 9; ++i) {
    const auto t0 = Clock::now();
    CHECK(to_lab2.top("veth " + made_up_word(0)) == "{move left}");
    round_trips.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  // One line each on standard output (ctest -V shows them; scripts/bench dds prints them).
  std::ostringstream all;
  if (times.size() <= 10)
    for (double t : times) all << " " << std::lround(t);
  std::cout << "test_dds_veth: replication across the veth pair (define answered at lab1 on host "
               "A -> parsed at lab2 on host B), "
            << times.size() << " definitions: median " << std::lround(median(times))
            << " ms, 90th percentile " << std::lround(percentile(times, 0.9)) << " ms, max "
            << std::lround(percentile(times, 1.0)) << " ms"
            << (all.str().empty() ? "" : "; each (ms):" + all.str()) << std::endl;
  std::cout << "test_dds_veth: a query's round trip across the pair (operator on A -> lab2 on "
               "B): median "
            << std::round(median(round_trips) * 10) / 10 << " ms" << std::endl;

  // robot1 (host B) plans; its plan reaches the operator (host A): visit room3 from (10,7) is
  // 4 poses, the first at x = 10 m (world.resolution 1, origin 0), as on loopback
  // (test_dds_node).
  REQUIRE(to_robot1.call({{"op", "world"}, {"world", study_world_with_robot(10, 7)}})["ok"] ==
          true);
  REQUIRE(!to_robot1.call({{"op", "query"}, {"text", "visit room3"}})["candidates"].empty());
  REQUIRE(to_robot1.call({{"op", "accept"}, {"rank", 0}})["ok"] == true);
  std::vector<std::pair<std::uint32_t, double>> got;
  CHECK(plans.next([&](const nav_msgs_msg_dds__Path_& p) {
    got.emplace_back(p.poses_._length, p.poses_._buffer[0].pose_.position_.x_);
  }));
  CHECK(got == std::vector<std::pair<std::uint32_t, double>>{{4, 10.0}});

  // Every node stops within the bound on SIGTERM, in its namespace too.
  std::ostringstream stops;
  for (Node* n : {&lab1, &lab2, &robot1}) {
    const auto [status, took] = n->stop();
    INFO(n->text());
    INFO("SIGTERM to exit: " << took.count() << " ms");
    CHECK(status == 0);
    CHECK(took <= kStopBound);
    CHECK(n->text().find("flipper dds: stopped after") != std::string::npos);
    stops << " " << took.count();
  }
  std::cout << "test_dds_veth: SIGTERM to exit (ms), lab1 on A, lab2 and robot1 on B:"
            << stops.str() << std::endl;
  std::filesystem::remove_all(dir);
}

// Loopback that is loopback (apps/dds/loopback_sockets.hpp): with the default configuration no
// UDP socket of a Flipper DDS process is bound to a non-loopback or wildcard address. The
// sockets are read from the kernel's tables here, independently of Flipper's own check
// (/proc/<pid>/fd socket inodes matched against /proc/<pid>/net/udp and udp6), and printed.
#include <cstdio>
#include <iostream>

#include "dds_test_support.hpp"
#include "flipper/dds/request_node.hpp"
#include "flipper/msg/SessionLine.h"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

struct Bound {
  std::string local;  // as the kernel prints it: hex address ':' hex port
  bool v6 = false;
};

std::vector<Bound> bound_udp(pid_t pid) {
  std::set<unsigned long> inodes;
  for (const auto& fd :
       std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/fd")) {
    std::error_code ec;
    const std::string link = std::filesystem::read_symlink(fd.path(), ec).string();
    unsigned long inode = 0;
    if (!ec && std::sscanf(link.c_str(), "socket:[%lu]", &inode) == 1) inodes.insert(inode);
  }
  std::vector<Bound> out;
  for (const bool v6 : {false, true}) {
    std::ifstream table("/proc/" + std::to_string(pid) + "/net/udp" + (v6 ? "6" : ""));
    std::string line;
    std::getline(table, line);
    while (std::getline(table, line)) {
      char local[64] = {};
      unsigned long inode = 0;
      if (std::sscanf(line.c_str(), " %*d: %63s %*s %*x %*s %*s %*s %*d %*d %lu", local, &inode) ==
              2 &&
          inodes.count(inode))
        out.push_back({local, v6});
    }
  }
  return out;
}

// 127.0.0.0/8 in the kernel's (little-endian) hex, or ::1.
bool loopback(const Bound& b) {
  const std::string address = b.local.substr(0, b.local.find(':'));
  if (!b.v6) return address.size() == 8 && address.substr(6) == "7F";
  return address == "00000000000000000000000001000000";
}

std::string shown(const std::vector<Bound>& sockets) {
  std::string out;
  for (const auto& b : sockets) out += (b.v6 ? " udp6 " : " udp ") + b.local;
  return out;
}

/// A client writer on `topic`, matched once a node reads it.
bool node_listening(dds::Participant& p, const std::string& topic) {
  dds::Qos qos;
  dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
  const dds_entity_t w = dds_create_writer(
      p.handle(), p.topic(&flipper_msg_dds__SessionLine__desc, topic), qos.q, nullptr);
  const bool matched = wait_until([&] {
    dds_publication_matched_status_t st;
    return dds_get_publication_matched_status(w, &st) == 0 && st.current_count > 0;
  });
  dds_delete(w);
  return matched;
}

}  // namespace

TEST_CASE("no socket of flipper dds leaves loopback with the default configuration", "[dds]") {
  const int domain = test_domain();
  ensure_loopback_env();
  // The child gets Flipper's generated configuration: no CYCLONEDDS_URI in its environment. It
  // starts before this process has DDS sockets, so it inherits none (Cyclone's sockets are not
  // close-on-exec).
  const std::string uri = std::getenv("CYCLONEDDS_URI");
  unsetenv("CYCLONEDDS_URI");
  testsupport::ChildProcess node({flipper_bin(), "dds", "--set",
                                  "dds.domain=" + std::to_string(domain), "--set",
                                  "lexicon.path=:memory:", "--set", "publish.plans=dds"});
  setenv("CYCLONEDDS_URI", uri.c_str(), 1);
  auto participant = test_participant(domain);
  REQUIRE(node_listening(*participant, dds::kRequestTopic));
  const auto sockets = bound_udp(node.pid());
  std::cout << "flipper dds (pid " << node.pid() << ") UDP sockets:" << shown(sockets) << "\n";
  INFO("flipper dds:" << shown(sockets));
  // Discovery and data receive ports (7400 + 250 d + 10 + 2 i, + 1) and a transmit socket.
  CHECK(sockets.size() == 3);
  for (const auto& b : sockets) CHECK(loopback(b));
  // The test's own participant is loopback-only too.
  const auto own = bound_udp(::getpid());
  std::cout << "test process (pid " << ::getpid() << ") UDP sockets:" << shown(own) << "\n";
  INFO("test process:" << shown(own));
  CHECK(own.size() == 3);
  for (const auto& b : own) CHECK(loopback(b));
  kill(node.pid(), SIGTERM);
  CHECK(node.finish() == 0);
}

#pragma once
/// @file loopback_sockets.hpp
/// Loopback that is loopback (docs/ros2.md, "Loopback by default"). Cyclone DDS
/// 0.10.2 binds its unicast receive sockets (discovery and data) to the wildcard address whatever
/// interfaces its configuration selects; no setting changes that. While a LoopbackBinds is alive,
/// this process binds such a socket to the loopback address of the same family instead
/// (127.0.0.1 or ::1), so nothing off the machine can reach it. Participant holds one while it
/// creates a loopback-only domain, then checks the result with udp_sockets().

#include <sys/types.h>

#include <string>
#include <vector>

namespace flipper::dds {

class LoopbackBinds {
 public:
  LoopbackBinds();
  ~LoopbackBinds();
  LoopbackBinds(const LoopbackBinds&) = delete;
  LoopbackBinds& operator=(const LoopbackBinds&) = delete;
};

/// A bound UDP socket of a process: local address as text ("127.0.0.1", "::", ...) and port.
struct UdpSocket {
  std::string address;
  unsigned port = 0;
  bool loopback() const;
};

/// The UDP sockets process `pid` holds (its /proc/<pid>/fd matched against the socket tables
/// /proc/<pid>/net/udp and udp6). Empty when they cannot be read.
std::vector<UdpSocket> udp_sockets(pid_t pid);

}  // namespace flipper::dds

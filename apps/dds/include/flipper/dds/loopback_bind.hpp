#pragma once
/// @file loopback_bind.hpp
/// The bind() that keeps Cyclone DDS on loopback (loopback_sockets.hpp), header-only and on libc
/// alone, so that an executable that loads the DDS code later (flipper and its dds front-end
/// module, apps/cli/loopback_bind.cpp) can define it: libddsc's calls bind to the executable's
/// definition, never to one in a module. Such an executable also exports the switch
/// (kLoopbackBindsSymbol), which LoopbackBinds then turns instead of its own.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstring>

namespace flipper::dds {

/// The exported name of an executable's switch: an extern "C" std::atomic<int>, non-zero while
/// some LoopbackBinds is alive.
inline constexpr const char* kLoopbackBindsSymbol = "flipper_dds_loopback_binds";

/// bind(2); while `active`, a wildcard address of a UDP socket is replaced by the loopback
/// address of its family.
inline int loopback_bind(bool active, int fd, const sockaddr* addr, socklen_t len) noexcept {
  const auto system_bind = [fd](const sockaddr* a, socklen_t l) {
    return static_cast<int>(syscall(SYS_bind, fd, a, l));
  };
  int type = 0;
  socklen_t size = sizeof type;
  if (!active || addr == nullptr || getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &size) != 0 ||
      type != SOCK_DGRAM)
    return system_bind(addr, len);
  if (addr->sa_family == AF_INET && len >= sizeof(sockaddr_in)) {
    sockaddr_in a;
    std::memcpy(&a, addr, sizeof a);
    if (a.sin_addr.s_addr == htonl(INADDR_ANY)) {
      a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      return system_bind(reinterpret_cast<const sockaddr*>(&a), sizeof a);
    }
  } else if (addr->sa_family == AF_INET6 && len >= sizeof(sockaddr_in6)) {
    sockaddr_in6 a;
    std::memcpy(&a, addr, sizeof a);
    if (IN6_IS_ADDR_UNSPECIFIED(&a.sin6_addr)) {
      a.sin6_addr = in6addr_loopback;
      return system_bind(reinterpret_cast<const sockaddr*>(&a), sizeof a);
    }
  }
  return system_bind(addr, len);
}

}  // namespace flipper::dds

// LoopbackBinds and udp_sockets (loopback_sockets.hpp). bind() below replaces libc's in the
// executables that link flipper_dds: the dynamic linker resolves libddsc's bind() to the
// executable's definition first. Outside a LoopbackBinds, or for anything but a wildcard UDP
// bind, it is the plain system call. In a module (flipper's dds front end) this bind() is not the
// one libddsc calls: flipper defines it (loopback_bind.hpp) and exports the switch, found here.
#include "flipper/dds/loopback_sockets.hpp"

#include <arpa/inet.h>
#include <dlfcn.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "flipper/dds/cyclone_config.hpp"
#include "flipper/dds/loopback_bind.hpp"

namespace flipper::dds {
namespace {

std::atomic<int> g_loopback_binds{0};

/// The executable's switch when it exports one (its bind() is the one libddsc calls), else ours.
std::atomic<int>& loopback_binds() {
  static std::atomic<int>* const on = [] {
    void* exported = dlsym(RTLD_DEFAULT, kLoopbackBindsSymbol);
    return exported != nullptr ? static_cast<std::atomic<int>*>(exported) : &g_loopback_binds;
  }();
  return *on;
}

// The socket inodes among a process's open files.
std::set<std::string> socket_inodes(pid_t pid) {
  std::set<std::string> out;
  std::error_code ec;
  const std::filesystem::path fds = "/proc/" + std::to_string(pid) + "/fd";
  for (const auto& entry : std::filesystem::directory_iterator(fds, ec)) {
    const std::string target = std::filesystem::read_symlink(entry.path(), ec).string();
    if (!ec && target.rfind("socket:[", 0) == 0) out.insert(target.substr(8, target.size() - 9));
  }
  return out;
}

// "0100007F:23C8" (IPv4, the kernel's byte order) or 32 hex digits and a port (IPv6).
UdpSocket decode(const std::string& local, bool v6) {
  UdpSocket s;
  const auto colon = local.find(':');
  const std::string hex = local.substr(0, colon);
  s.port = static_cast<unsigned>(std::stoul(local.substr(colon + 1), nullptr, 16));
  char text[INET6_ADDRSTRLEN] = {};
  if (!v6) {
    in_addr a{};
    a.s_addr = static_cast<std::uint32_t>(std::stoul(hex, nullptr, 16));
    inet_ntop(AF_INET, &a, text, sizeof text);
  } else {
    in6_addr a{};
    for (std::size_t word = 0; word < 4; ++word) {
      const auto w = static_cast<std::uint32_t>(std::stoul(hex.substr(8 * word, 8), nullptr, 16));
      std::memcpy(&a.s6_addr[4 * word], &w, 4);
    }
    inet_ntop(AF_INET6, &a, text, sizeof text);
  }
  s.address = text;
  return s;
}

}  // namespace

LoopbackBinds::LoopbackBinds() {
  loopback_binds().fetch_add(1);
}
LoopbackBinds::~LoopbackBinds() {
  loopback_binds().fetch_sub(1);
}

bool UdpSocket::loopback() const {
  return loopback_address(address);
}

std::vector<UdpSocket> udp_sockets(pid_t pid) {
  const std::set<std::string> inodes = socket_inodes(pid);
  std::vector<UdpSocket> out;
  for (const bool v6 : {false, true}) {
    std::ifstream table("/proc/" + std::to_string(pid) + "/net/udp" + (v6 ? "6" : ""));
    std::string line;
    std::getline(table, line);  // header
    while (std::getline(table, line)) {
      std::istringstream fields(line);
      std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
      fields >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >>
          timeout >> inode;
      if (fields && inodes.count(inode)) out.push_back(decode(local, v6));
    }
  }
  return out;
}

}  // namespace flipper::dds

// Default visibility: exported from the executable, so the dynamic linker binds libddsc's calls
// to it (the build hides symbols by default).
extern "C" __attribute__((visibility("default"))) int bind(int fd, const sockaddr* addr,
                                                           socklen_t len) noexcept {
  return flipper::dds::loopback_bind(flipper::dds::loopback_binds().load() != 0, fd, addr, len);
}

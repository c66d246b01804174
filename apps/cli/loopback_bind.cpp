// flipper's bind() (flipper/dds/loopback_bind.hpp): the dds front-end module is loaded after
// libc, so Cyclone DDS's bind() calls resolve to the executable's definition only; this is it,
// with the switch the module's LoopbackBinds turns (found by its exported name). Outside a
// LoopbackBinds it is the plain system call. Libc alone: flipper still maps no DDS library.
#include <atomic>

#include "flipper/dds/loopback_bind.hpp"

extern "C" {

// Default visibility: exported (the build hides symbols by default), see loopback_bind.hpp.
__attribute__((visibility("default"))) std::atomic<int> flipper_dds_loopback_binds{0};

__attribute__((visibility("default"))) int bind(int fd, const sockaddr* addr,
                                                socklen_t len) noexcept {
  return flipper::dds::loopback_bind(flipper_dds_loopback_binds.load() != 0, fd, addr, len);
}
}

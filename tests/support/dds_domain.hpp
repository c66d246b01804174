#pragma once
// A DDS domain id of this process's own, for tests and benchmarks (free of Catch2). Several
// checkouts run their suites at once on one machine; each DDS test process claims a domain by
// holding an flock on /tmp/flipper-dds-domain-<id>.lock, kept until the process exits (the kernel
// drops the lock then, even after SIGKILL), so no two live processes share a domain.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <stdexcept>
#include <string>

namespace flipper::testsupport {

/// Domains 170..230: DDS allows 0..232; security governance documents cover 0..230.
inline constexpr int kFirstTestDomain = 170;
inline constexpr int kLastTestDomain = 230;

/// The same id on every call in one process; throws when every domain is taken.
inline int claimed_dds_domain() {
  static const int domain = [] {
    for (int id = kFirstTestDomain; id <= kLastTestDomain; ++id) {
      const std::string path = "/tmp/flipper-dds-domain-" + std::to_string(id) + ".lock";
      const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
      if (fd < 0) continue;
      if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return id;  // fd stays open: the claim
      ::close(fd);
    }
    throw std::runtime_error("every DDS test domain (170..230) is claimed by another process");
  }();
  return domain;
}

}  // namespace flipper::testsupport

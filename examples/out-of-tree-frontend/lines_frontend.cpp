// `lines`: a tiny front end (flipper/sdk/frontend.hpp). It listens on a loopback TCP port; each
// connection is one session; each line it receives is one session-protocol request, answered with
// one line by the host. Single-threaded: poll() over the listening socket and the connections,
// waking every 100 ms to see whether flipper was asked to stop.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <flipper/sdk/errors.hpp>
#include <flipper/sdk/frontend.hpp>
#include <map>
#include <string>
#include <vector>

namespace {

using flipper::sdk::Error;
using flipper::sdk::FrontendHost;

struct Connection {
  FrontendHost::SessionId session = 0;
  std::string pending;  // received bytes after the last newline
};

bool write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::send(fd, text.data() + done, text.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

class Lines final : public flipper::sdk::Frontend {
 public:
  explicit Lines(const flipper::sdk::Params& p)
      : host_(p.get_string("host")),
        port_(static_cast<int>(p.get_int("port"))),
        max_line_(static_cast<std::size_t>(p.get_int("max_line_bytes"))) {}

  static flipper::sdk::ParamSchema schema() {
    flipper::sdk::ParamSchema s;
    s.add_string("host", "127.0.0.1", "IPv4 address to listen on (loopback by default)");
    s.add_int("port", 0, "TCP port (0: any free port, printed at start)", 0, 65535);
    s.add_int("max_line_bytes", 1 << 20, "Longest request line; a longer one ends the connection",
              1, 1 << 30);
    return s;
  }

  int run(FrontendHost& host) override {
    const int listener = listen_socket();
    host.log("listening on " + host_ + ":" + std::to_string(bound_port(listener)));
    std::map<int, Connection> connections;
    std::size_t requests = 0;
    while (!host.stopping()) {
      std::vector<pollfd> fds{{listener, POLLIN, 0}};
      for (const auto& c : connections) fds.push_back({c.first, POLLIN, 0});
      if (::poll(fds.data(), fds.size(), 100) <= 0) continue;
      if ((fds[0].revents & POLLIN) != 0) {
        const int fd = ::accept(listener, nullptr, nullptr);
        if (fd >= 0) connections[fd].session = host.open_session();
      }
      for (std::size_t i = 1; i < fds.size(); ++i) {
        if (fds[i].revents == 0) continue;
        Connection& c = connections[fds[i].fd];
        char buf[4096];
        const ssize_t n = ::recv(fds[i].fd, buf, sizeof buf, 0);
        bool keep = n > 0;
        if (keep) c.pending.append(buf, static_cast<std::size_t>(n));
        for (std::size_t nl; keep && (nl = c.pending.find('\n')) != std::string::npos;) {
          const std::string answer = host.handle(c.session, c.pending.substr(0, nl));
          c.pending.erase(0, nl + 1);
          ++requests;
          if (!answer.empty()) keep = write_all(fds[i].fd, answer + "\n");
        }
        if (c.pending.size() > max_line_) keep = false;
        if (!keep) {
          host.close_session(c.session);
          ::close(fds[i].fd);
          connections.erase(fds[i].fd);
        }
      }
    }
    for (const auto& c : connections) {
      host.close_session(c.second.session);
      ::close(c.first);
    }
    ::close(listener);
    host.log("stopped after " + std::to_string(requests) + " requests");
    return 0;
  }

 private:
  int listen_socket() const {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port_));
    if (::inet_pton(AF_INET, host_.c_str(), &addr.sin_addr) != 1)
      throw Error(flipper::sdk::codes::kBadConfig,
                  "frontend.lines.host '" + host_ + "' is not an IPv4 address");
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const int on = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::listen(fd, 16) != 0) {
      const std::string why = std::strerror(errno);
      if (fd >= 0) ::close(fd);
      throw Error("listen_failed",
                  "cannot listen on " + host_ + ":" + std::to_string(port_) + ": " + why);
    }
    return fd;
  }

  static int bound_port(int fd) {
    sockaddr_in addr{};
    socklen_t len = sizeof addr;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
    return ntohs(addr.sin_port);
  }

  std::string host_;
  int port_;
  std::size_t max_line_;
};

}  // namespace

FLIPPER_FRONTEND(Lines, "lines", FLIPPER_PLUGIN_VERSION,
                 "The session protocol over TCP lines, one session per connection")

// flipper serve, run by flipper-frontends (frontends.hpp): the web front end (Flipper Studio) and
// the session protocol over HTTP, until SIGINT/SIGTERM. See apps/studio and README "Flipper
// Studio".
#include <csignal>
#include <iostream>
#include <thread>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/studio/server.hpp"

namespace flipper::cli {

int run_serve(const CommonOptions& opts) {
  const kernel::Config config = load_config(opts);
  // Signals go to one waiting thread that stops the server (httplib's stop is not
  // async-signal-safe); block them before any server thread starts.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  // SIGUSR1 is how the main thread wakes the waiter when listen() returns on its own.
  sigaddset(&signals, SIGUSR1);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  studio::Server server(config);
  const auto& o = server.options();
  if (!studio::is_loopback(o.host))
    std::cerr << "flipper serve: warning: listening on " << o.host
              << ", which is not a loopback address: anyone who can reach it can use this "
                 "server\n";
  const int port = server.bind();
  std::cout << "flipper serve: listening on http://" << o.host << ":" << port << "/" << std::endl;
  if (o.sempre)
    std::cout << "flipper serve: the 2018 server's API at http://" << o.host << ":" << port
              << "/sempre, open to every web page (docs/sempre.md)" << std::endl;
  std::thread waiter([&server, signals] {
    int sig = 0;
    sigwait(&signals, &sig);
    server.stop();
  });
  server.listen();
  // listen() also returns when binding breaks: wake the waiter so it can be joined.
  pthread_kill(waiter.native_handle(), SIGUSR1);
  waiter.join();
  std::cout << "flipper serve: stopped" << std::endl;
  return kExitOk;
}

}  // namespace flipper::cli

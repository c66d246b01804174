// flipper serve, in the serve front-end module (frontend_module.hpp): the web front end (Flipper
// Studio) and the session protocol over HTTP, until SIGINT/SIGTERM. See docs/studio.md.
#include <csignal>
#include <iostream>
#include <thread>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/naturalization/config_keys.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/studio/server.hpp"
#include "sanitizer_build.hpp"

namespace flipper::cli {

int serve_main(const CommonOptions& opts) {
  set_server_isolation();  // docs/plugins-untrusted.md §6
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
  // A file-size limit (ulimit -f) makes a write fail with EFBIG, answered write_failed like a
  // full disk, instead of killing the server (docs/studio.md §7 "Nothing lost silently").
  std::signal(SIGXFSZ, SIG_IGN);

  studio::Server server(config);
  const auto& o = server.options();
  if (!studio::is_loopback(o.host))
    std::cerr << "flipper serve: warning: listening on " << o.host
              << ", which is not a loopback address: anyone who can reach it can use this "
                 "server\n";
  if (server.connection_cap() < o.max_connections)
    std::cerr << "flipper serve: at most " << server.connection_cap()
              << " connections at once (serve.max_connections is " << o.max_connections
              << "; the descriptor limit, ulimit -n, allows no more)" << std::endl;
  const int port = server.bind();
  const char* scheme = o.tls_cert.empty() ? "http://" : "https://";  // docs/serve.md "HTTPS"
  std::cout << "flipper serve: listening on " << scheme << o.host << ":" << port << "/"
            << std::endl;
  if (o.sempre)
    std::cout << "flipper serve: the 2018 server's API at " << scheme << o.host << ":" << port
              << "/sempre, for this page and serve.sempre_origins (docs/sempre.md)" << std::endl;
  std::thread waiter([&server, signals] {
    int sig = 0;
    sigwait(&signals, &sig);
    server.stop();
  });
  server.listen();
  // listen() also returns when binding breaks: wake the waiter so it can be joined.
  pthread_kill(waiter.native_handle(), SIGUSR1);
  waiter.join();
  // Group commit's counters (docs/naturalization.md §5 "Group commit"): the kernels' writes and
  // the WAL syncs they shared.
  if (const std::string path = config.text(naturalization::keys::kLexiconPath);
      !path.empty() && path != ":memory:") {
    const auto group = naturalization::group_commit_stats(
        config.resolve_path_of(naturalization::keys::kLexiconPath, path));
    if (group.writes > 0)
      std::cout << "flipper serve: lexicon group commit: " << group.writes << " writes, "
                << group.syncs << " syncs" << std::endl;
  }
  std::cout << "flipper serve: stopped" << std::endl;
  return kExitOk;
}

}  // namespace flipper::cli

// flipper dds, run by flipper-frontends (frontends.hpp): a DDS node answering session-protocol
// requests from rt/<ns>/flipper/request on rt/<ns>/flipper/answer (apps/dds/request_node.hpp), with
// the config's other DDS services (plans, lexicon replication). Runs until SIGINT/SIGTERM.
#include <atomic>
#include <csignal>
#include <iostream>

#include "commands.hpp"
#include "common.hpp"
#include "dds_services.hpp"
#include "flipper/dds/request_node.hpp"

namespace flipper::cli {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) {
  g_stop.store(true);
}

}  // namespace

int run_dds_node(const CommonOptions& opts) {
  wiring::SessionHost host = wiring::open_host(config_file(opts), opts.overrides);
  const DdsServices services = DdsServices::start(host, /*force_participant=*/true);
  dds::RequestNode node(
      services.participant, [&] { return services.open(host); }, std::cerr,
      host.runtime->config.get_string("dds.namespace"));
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::cerr << "flipper dds: serving " << node.request_topic() << " -> " << node.answer_topic()
            << " on DDS domain " << services.participant->domain() << std::endl;
  node.run(g_stop);
  std::cerr << "flipper dds: stopped after " << node.answered() << " answers, " << node.dropped()
            << " dropped requests" << std::endl;
  return kExitOk;
}

}  // namespace flipper::cli

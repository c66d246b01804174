#pragma once
// Inside the dds front-end module (frontend_module.hpp): the DDS services of apps/dds a node or a
// session runs, plans out (publish.plans: dds) and lexicon replication (lexicon.replication:
// dds). One participant per process, created only when a service needs it (apps/dds/transport.hpp:
// loopback unless the config names interfaces).
#include <memory>

#include "dds_services.hpp"

namespace flipper::dds {
class Participant;
class PlanPublisher;
class Nav2Executor;
class LexiconReplicator;
}  // namespace flipper::dds

namespace flipper::cli {

struct NodeServices {
  std::shared_ptr<dds::Participant> participant;  // null: no DDS service configured
  std::shared_ptr<dds::PlanPublisher> plans;
  std::shared_ptr<dds::Nav2Executor> nav2;  // nav2.execute: Nav2 drives accepted plans
  std::shared_ptr<dds::LexiconReplicator> replicator;

  /// Starts what `host`'s config asks for (`force_participant`: the dds node always needs one).
  static NodeServices start(wiring::SessionHost& host, bool force_participant = false);
  /// A session of `host` with the services attached (plan observer, replication guards).
  std::unique_ptr<kernel::Session> open(const wiring::SessionHost& host) const;
  NodeServices() = default;
  NodeServices(NodeServices&&) = default;
  NodeServices& operator=(NodeServices&&) = default;
  NodeServices(const NodeServices&) = delete;
  NodeServices& operator=(const NodeServices&) = delete;
  ~NodeServices();
};

}  // namespace flipper::cli

#pragma once
// The DDS services a front end runs when its config asks for them (apps/dds): plans out
// (publish.plans: dds) and lexicon replication (lexicon.replication: dds). One participant per
// process, created only when a service needs it (apps/dds/transport.hpp: loopback unless the
// config names interfaces). Shared by `session`, `repl` and `dds`. In `flipper` itself start()
// execs flipper-frontends when a service is asked for (frontends.hpp).
#include <memory>

#include "flipper/dds/config_keys.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/naturalization/config_keys.hpp"

#include "flipper/wiring/session_factory.hpp"

namespace flipper::dds {
class Participant;
class PlanPublisher;
class LexiconReplicator;
}  // namespace flipper::dds

namespace flipper::cli {

/// The config asks for a DDS service: plans published on DDS or lexicon replication over DDS.
inline bool wants_dds_services(const kernel::Config& config) {
  return config.get(dds::keys::kPublishPlans) == dds::keys::Plans::dds ||
         config.get(naturalization::keys::kReplication) == naturalization::keys::Replication::dds;
}

struct DdsServices {
  std::shared_ptr<dds::Participant> participant;  // null: no DDS service configured
  std::shared_ptr<dds::PlanPublisher> plans;
  std::shared_ptr<dds::LexiconReplicator> replicator;

  /// Starts what `host`'s config asks for (`force_participant`: the dds node always needs one).
  static DdsServices start(wiring::SessionHost& host, bool force_participant = false);
  /// A session of `host` with the services attached (plan observer, replication guards).
  std::unique_ptr<kernel::Session> open(const wiring::SessionHost& host) const;
  ~DdsServices();
};

}  // namespace flipper::cli

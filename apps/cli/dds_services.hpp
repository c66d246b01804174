#pragma once
// The DDS services a session runs when its config asks for them (apps/dds): plans out
// (publish.plans: dds) and lexicon replication (lexicon.replication: dds). They live in the dds
// front-end module (frontend_module.hpp), which start() loads only when a service is asked for,
// so a study run never maps Cyclone DDS. Shared by `session` and `repl`.
#include <functional>
#include <memory>

#include "flipper/dds/config_keys.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/kernel/session.hpp"
#include "flipper/naturalization/config_keys.hpp"
#include "flipper/wiring/session_factory.hpp"

namespace flipper::cli {

/// The config asks for a DDS service: plans published on DDS or sent to Nav2, or lexicon
/// replication over DDS.
inline bool wants_dds_services(const kernel::Config& config) {
  return config.get(dds::keys::kPublishPlans) == dds::keys::Plans::dds ||
         config.get(dds::keys::kNav2Execute) ||
         config.get(naturalization::keys::kReplication) == naturalization::keys::Replication::dds;
}

struct DdsServices {
  /// The module's running services (participant, publisher, replicator); null: none configured.
  std::shared_ptr<void> running;
  /// Opens a session with the services attached (plan observer, replication guards); empty:
  /// none configured. Declared after `running`, so destroyed before it.
  std::function<std::unique_ptr<kernel::Session>(const wiring::SessionHost&)> opener;

  /// Starts what `host`'s config asks for, in the dds module (frontend_host.cpp).
  static DdsServices start(wiring::SessionHost& host);
  /// A session of `host` with the services attached.
  std::unique_ptr<kernel::Session> open(const wiring::SessionHost& host) const {
    return opener ? opener(host) : host.open();
  }
};

}  // namespace flipper::cli

#include "dds_node_services.hpp"

#include <iostream>

#include "flipper/dds/config_keys.hpp"
#include "flipper/dds/keystore.hpp"
#include "flipper/dds/lexicon_replicator.hpp"
#include "flipper/dds/names.hpp"
#include "flipper/dds/nav2_executor.hpp"
#include "flipper/dds/participant.hpp"
#include "flipper/dds/plan_publisher.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::cli {

NodeServices NodeServices::start(wiring::SessionHost& host, bool force_participant) {
  const kernel::Config& config = host.runtime->config;
  const bool plans = config.get(dds::keys::kPublishPlans) == dds::keys::Plans::dds;
  const bool nav2 = config.get(dds::keys::kNav2Execute);
  const bool replicate =
      config.get(naturalization::keys::kReplication) == naturalization::keys::Replication::dds;
  NodeServices s;
  if (!wants_dds_services(config) && !force_participant) return s;
  const int dims =
      host.runtime->default_world.geometry ? host.runtime->default_world.geometry->dims() : 2;
  // Check everything before the participant exists.
  std::optional<dds::PlanFrame> frame;
  if (plans || nav2) frame = dds::PlanFrame::from_config(config, dims);
  const auto nav2_options = dds::Nav2Executor::options_from_config(config);
  if (replicate && config.get(naturalization::keys::kSite).empty())
    throw sdk::Error(sdk::codes::kBadConfig,
                     "lexicon.replication: dds needs this site's name in lexicon.site");
  const std::string ns = config.get(dds::keys::kNamespace);
  dds::check_namespace(ns);
  const auto security = dds::security_config(config);
  if (security && replicate && security->identity != config.get(naturalization::keys::kSite))
    throw sdk::Error(sdk::codes::kBadConfig,
                     "with DDS Security a site is its certificate: dds.security.identity '" +
                         security->identity + "' must be lexicon.site '" +
                         config.get(naturalization::keys::kSite) + "'");
  if (security && ns.empty() && (plans || nav2 || force_participant))
    throw sdk::Error(sdk::codes::kBadConfig,
                     "with DDS Security a node serves a namespace its permissions name: set "
                     "dds.namespace (`flipper dds security add` grants the identity's own name)");
  s.participant = std::make_shared<dds::Participant>(config, std::cerr);
  if (plans) s.plans = std::make_shared<dds::PlanPublisher>(s.participant, *frame, ns);
  if (nav2)
    s.nav2 = std::make_shared<dds::Nav2Executor>(s.participant, *frame, nav2_options, std::cerr);
  if (replicate)
    s.replicator = dds::LexiconReplicator::start(
        s.participant, host, std::cerr,
        security ? std::optional<dds::Keystore>(security->keystore) : std::nullopt);
  return s;
}

std::unique_ptr<kernel::Session> NodeServices::open(const wiring::SessionHost& host) const {
  auto session = host.open();
  if (plans) session->install(plans);
  if (nav2) session->install(nav2);
  if (replicator)  // a weak reference: the replicator's thread stops before the sessions go
    session->install(kernel::make_extension([weak = std::weak_ptr(replicator)](kernel::Session& s) {
      if (auto r = weak.lock()) r->attach(s);
    }));
  return session;
}

NodeServices::~NodeServices() {
  // The replicator's thread stops before the participant it reads from goes.
  replicator.reset();
  plans.reset();
  nav2.reset();  // its worker stops before the participant goes
  participant.reset();
}

}  // namespace flipper::cli

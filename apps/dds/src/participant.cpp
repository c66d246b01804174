#include "flipper/dds/participant.hpp"

#include <unistd.h>

#include <cstdlib>
#include <mutex>
#include <optional>
#include <ostream>

#include "flipper/dds/keystore.hpp"
#include "flipper/dds/loopback_sockets.hpp"

#include "flipper/dds/config_keys.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::dds {

dds_return_t check(dds_return_t rc, const std::string& what) {
  if (rc < 0) throw sdk::Error("dds_error", what + ": " + dds_strretcode(rc));
  return rc;
}

namespace {

std::vector<std::pair<std::string, std::string>> configured_security(const kernel::Config& config,
                                                                     std::ostream& log) {
  const auto sc = security_config(config);
  if (!sc) return {};
  log << "flipper: DDS Security on: identity '" << sc->identity << "' of keystore "
      << sc->keystore.dir << std::endl;
  return security_properties(sc->keystore, sc->identity);
}

}  // namespace

Participant::Participant(const kernel::Config& config, std::ostream& log)
    : Participant(static_cast<int>(config.get(keys::kDomain)),
                  choose_transport(config, std::getenv("CYCLONEDDS_URI")), log,
                  configured_security(config, log)) {}

Participant::Participant(int domain, const Transport& transport, std::ostream& log,
                         const std::vector<std::pair<std::string, std::string>>& security)
    : domain_(domain), transport_(transport), secure_(!security.empty()) {
  log << "flipper: " << transport_.describe(domain_) << std::endl;
  Qos qos;
  for (const auto& [name, value] : security) dds_qset_prop(qos.q, name.c_str(), value.c_str());
  const auto id = static_cast<dds_domainid_t>(domain_);
  {
    // One creation at a time, so LoopbackBinds covers only loopback-only domains' sockets.
    static std::mutex creating;
    std::lock_guard lock(creating);
    std::optional<LoopbackBinds> loopback;
    if (transport_.loopback_only) loopback.emplace();
    // dds_create_domain never reads CYCLONEDDS_URI: the XML chosen above is the whole config.
    const dds_entity_t d = dds_create_domain(id, transport_.xml.c_str());
    if (d < 0 && d != DDS_RETCODE_PRECONDITION_NOT_MET)  // already created in this process
      check(d, "creating DDS domain " + std::to_string(domain_));
    if (d >= 0) domain_entity_ = d;
    participant_ = dds_create_participant(id, qos.q, nullptr);
  }
  if (participant_ < 0) {
    if (domain_entity_ > 0) dds_delete(domain_entity_);
    check(participant_, "creating a DDS participant in domain " + std::to_string(domain_) +
                            (secure_ ? " (DDS Security: Cyclone's log above says why)" : ""));
  }
  if (transport_.loopback_only) check_sockets_on_loopback();
}

void Participant::check_sockets_on_loopback() {
  for (const UdpSocket& s : udp_sockets(::getpid()))
    if (!s.loopback()) {
      dds_delete(participant_);
      participant_ = 0;
      if (domain_entity_ > 0) dds_delete(domain_entity_);
      domain_entity_ = 0;
      throw sdk::Error("dds_error", "a UDP socket of this process is bound to " + s.address + ":" +
                                        std::to_string(s.port) +
                                        ", not loopback, though the DDS configuration is "
                                        "loopback only; the participant was not created");
    }
}

Participant::~Participant() {
  if (participant_ > 0) dds_delete(participant_);
  if (domain_entity_ > 0) dds_delete(domain_entity_);
}

dds_entity_t Participant::topic(const dds_topic_descriptor_t* descriptor, const std::string& name) {
  return check(dds_create_topic(participant_, descriptor, name.c_str(), nullptr, nullptr),
               "creating DDS topic '" + name + "'");
}

void ros_default_qos(Qos& qos, int depth) {
  dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(qos.q, DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos.q, DDS_HISTORY_KEEP_LAST, depth);
}

void latched_qos(Qos& qos) {
  dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(qos.q, DDS_DURABILITY_TRANSIENT_LOCAL);
  dds_qset_history(qos.q, DDS_HISTORY_KEEP_LAST, 1);
}

void history_qos(Qos& qos) {
  dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
  dds_qset_durability(qos.q, DDS_DURABILITY_TRANSIENT_LOCAL);
  dds_qset_history(qos.q, DDS_HISTORY_KEEP_ALL, DDS_LENGTH_UNLIMITED);
  dds_qset_resource_limits(qos.q, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
}

}  // namespace flipper::dds

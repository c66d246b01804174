#include "flipper/dds/participant.hpp"

#include <cstdlib>
#include <ostream>

#include "flipper/kernel/config.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::dds {

dds_return_t check(dds_return_t rc, const std::string& what) {
  if (rc < 0) throw sdk::Error("dds_error", what + ": " + dds_strretcode(rc));
  return rc;
}

Participant::Participant(const kernel::Config& config, std::ostream& log)
    : Participant(static_cast<int>(config.get_int("dds.domain")),
                  choose_transport(config, std::getenv("CYCLONEDDS_URI")), log) {}

Participant::Participant(int domain, const Transport& transport, std::ostream& log)
    : domain_(domain), transport_(transport) {
  log << "flipper: " << transport_.describe(domain_) << std::endl;
  const auto id = static_cast<dds_domainid_t>(domain_);
  // dds_create_domain never reads CYCLONEDDS_URI: the XML chosen above is the whole config.
  const dds_entity_t d = dds_create_domain(id, transport_.xml.c_str());
  if (d < 0 && d != DDS_RETCODE_PRECONDITION_NOT_MET)  // already created in this process
    check(d, "creating DDS domain " + std::to_string(domain_));
  if (d >= 0) domain_entity_ = d;
  participant_ = dds_create_participant(id, nullptr, nullptr);
  if (participant_ < 0) {
    if (domain_entity_ > 0) dds_delete(domain_entity_);
    check(participant_, "creating a DDS participant in domain " + std::to_string(domain_));
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

void history_qos(Qos& qos) {
  dds_qset_reliability(qos.q, DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
  dds_qset_durability(qos.q, DDS_DURABILITY_TRANSIENT_LOCAL);
  dds_qset_history(qos.q, DDS_HISTORY_KEEP_ALL, DDS_LENGTH_UNLIMITED);
  dds_qset_resource_limits(qos.q, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
}

}  // namespace flipper::dds

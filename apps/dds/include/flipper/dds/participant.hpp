#pragma once
/// @file participant.hpp
/// A Cyclone DDS domain participant created only through transport.hpp's rule, plus the QoS and
/// entity helpers the Flipper nodes share. Cyclone's C API: entities are integer handles,
/// negative on failure.

#include <dds/dds.h>

#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "flipper/dds/transport.hpp"

namespace flipper::kernel {
class Config;
}

namespace flipper::dds {

/// Throws sdk::Error("dds_error") with Cyclone's message when `rc` is negative.
dds_return_t check(dds_return_t rc, const std::string& what);

/// Owns the domain (created with the chosen XML, never from the environment directly) and one
/// participant; deletes both on destruction.
class Participant {
 public:
  /// Chooses the transport (transport.hpp), prints Transport::describe to `log`, creates the
  /// domain `dds.domain` and a participant. A loopback-only one binds its sockets to loopback
  /// (loopback_sockets.hpp) and checks that every UDP socket of the process is on loopback.
  /// Throws sdk::Error (bad_config, dds_error).
  Participant(const kernel::Config& config, std::ostream& log);
  /// Explicit domain and transport (tests and benchmarks); `security`: the DDS Security
  /// participant properties (keystore.hpp security_properties), empty for none.
  Participant(int domain, const Transport& transport, std::ostream& log,
              const std::vector<std::pair<std::string, std::string>>& security = {});
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  dds_entity_t handle() const { return participant_; }
  int domain() const { return domain_; }
  const Transport& transport() const { return transport_; }
  bool secure() const { return secure_; }

  /// A topic of `descriptor` named `name` (created once per name).
  dds_entity_t topic(const dds_topic_descriptor_t* descriptor, const std::string& name);

 private:
  void check_sockets_on_loopback();

  int domain_;
  Transport transport_;
  bool secure_ = false;
  dds_entity_t domain_entity_ = 0;
  dds_entity_t participant_ = 0;
};

/// QoS holder (deleted on destruction).
struct Qos {
  dds_qos_t* q = dds_create_qos();
  ~Qos() { dds_delete_qos(q); }
  Qos() = default;
  Qos(const Qos&) = delete;
  Qos& operator=(const Qos&) = delete;
};

/// Reliable, volatile, keep-last `depth`: ROS 2's default QoS profile.
void ros_default_qos(Qos& qos, int depth = 10);
/// Reliable, TRANSIENT_LOCAL, keep-last 1: a latched topic (the last plan, an action's status).
void latched_qos(Qos& qos);
/// Reliable, TRANSIENT_LOCAL, keep-all: the lexicon history.
void history_qos(Qos& qos);

}  // namespace flipper::dds

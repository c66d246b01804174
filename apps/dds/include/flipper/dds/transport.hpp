#pragma once
/// @file transport.hpp
/// Which network a Cyclone DDS participant may use. The rule (docs/ros2.md):
/// Flipper never creates a participant unless the effective Cyclone configuration is loopback
/// only, or the Flipper config names the interfaces explicitly (`dds.interfaces`).
///   - `dds.interfaces: []` (default) and no `dds.config`: Flipper generates the loopback XML
///     (lo, no multicast, unicast peers on 127.0.0.1). A CYCLONEDDS_URI in the environment is
///     used only when it is itself loopback only; anything else is refused.
///   - `dds.config: XML or items`: used when it is loopback only, or when `dds.interfaces` names
///     every interface it selects; refused otherwise.
///   A user's configuration (CYCLONEDDS_URI, dds.config) is resolved as Cyclone resolves it
///   (cyclone_config.hpp: every item, every file, comments ignored) and Cyclone gets exactly
///   what was checked; a setting the check cannot prove loopback-only is refused. A loopback-only
///   participant also binds its sockets to loopback (loopback_sockets.hpp).
///   - `dds.interfaces: [eth0, ...]` without `dds.config`: Flipper generates XML for exactly
///     those interfaces (multicast as Cyclone decides for them).

#include <string>
#include <vector>

namespace flipper::kernel {
class Config;
}

namespace flipper::dds {

struct Transport {
  std::string xml;                      ///< the Cyclone XML passed to dds_create_domain
  std::vector<std::string> interfaces;  ///< interfaces (names or addresses) it selects
  bool loopback_only = true;
  std::string source;  ///< "generated loopback", "CYCLONEDDS_URI", "dds.config", ...
  /// One line for start-up logs: "DDS domain 7: interfaces lo (loopback only; generated ...)".
  std::string describe(int domain) const;
};

/// The loopback-only Cyclone XML.
std::string loopback_xml();
/// Cyclone XML selecting exactly these interfaces.
std::string interfaces_xml(const std::vector<std::string>& interfaces);
/// Whether a name or address is the loopback interface: `lo`, 127.0.0.0/8 or ::1.
bool is_loopback(const std::string& interface);

/// The transport for `dds.*` of `config` and the value of CYCLONEDDS_URI (null when unset).
/// Throws sdk::Error(bad_config) naming what is not allowed.
Transport choose_transport(const kernel::Config& config, const char* env_uri);

}  // namespace flipper::dds

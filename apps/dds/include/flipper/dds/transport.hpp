#pragma once
/// @file transport.hpp
/// Which network a Cyclone DDS participant may use. The rule (README "Flipper with ROS 2"):
/// Flipper never creates a participant unless the effective Cyclone configuration is loopback
/// only, or the Flipper config names the interfaces explicitly (`dds.interfaces`).
///   - `dds.interfaces: []` (default) and no `dds.config`: Flipper generates the loopback XML
///     (lo, no multicast, unicast peers on 127.0.0.1). A CYCLONEDDS_URI in the environment is
///     used only when it is itself loopback only; anything else is refused.
///   - `dds.config: XML`: used when it is loopback only, or when `dds.interfaces` names every
///     interface it selects; refused otherwise.
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

/// The loopback-only Cyclone XML (docs: /work/shared/docs/toolchain.md).
std::string loopback_xml();
/// Cyclone XML selecting exactly these interfaces.
std::string interfaces_xml(const std::vector<std::string>& interfaces);
/// Interfaces a Cyclone XML config selects (NetworkInterface name/address attributes and the
/// older NetworkInterfaceAddress element); empty when it selects none (Cyclone's default: any).
std::vector<std::string> selected_interfaces(const std::string& xml);
/// Whether a name or address is the loopback interface (lo, loopback, 127.x.y.z, ::1).
bool is_loopback(const std::string& interface);
/// Whether every address a config lists as a discovery peer is on loopback.
bool peers_on_loopback(const std::string& xml);

/// The transport for `dds.*` of `config` and the value of CYCLONEDDS_URI (null when unset).
/// Throws sdk::Error(bad_config) naming what is not allowed.
Transport choose_transport(const kernel::Config& config, const char* env_uri);

}  // namespace flipper::dds

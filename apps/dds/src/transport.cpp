// The loopback rule for Cyclone DDS (transport.hpp). A user's configuration is resolved and read
// as Cyclone reads it (cyclone_config.hpp); the rule looks at what selects the network.
#include "flipper/dds/transport.hpp"

#include <algorithm>

#include "flipper/dds/cyclone_config.hpp"

#include "flipper/dds/config_keys.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::dds {
namespace {

[[noreturn]] void refuse_transport(const std::string& message) {
  throw sdk::Error(sdk::codes::kBadConfig, message);
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

}  // namespace

std::string loopback_xml() {
  return "<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/>"
         "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>"
         "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>20"
         "</MaxAutoParticipantIndex><Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
         "</Domain></CycloneDDS>";
}

std::string interfaces_xml(const std::vector<std::string>& interfaces) {
  std::string xml = "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>";
  for (const auto& i : interfaces) {
    const bool address = i.find_first_not_of("0123456789.:abcdefABCDEF") == std::string::npos &&
                         i.find_first_of(".:") != std::string::npos;
    xml += std::string("<NetworkInterface ") + (address ? "address" : "name") + "=\"" + i + "\"/>";
  }
  return xml + "</Interfaces></General></Domain></CycloneDDS>";
}

bool is_loopback(const std::string& i) {
  return i == "lo" || loopback_address(i);
}

std::string Transport::describe(int domain) const {
  return "DDS domain " + std::to_string(domain) + ": interfaces " + join(interfaces) +
         (loopback_only ? " (loopback only; " : " (NOT loopback: named in dds.interfaces; ") +
         source + ")";
}

Transport choose_transport(const kernel::Config& config, const char* env_uri) {
  const std::vector<std::string> named = config.get(keys::kInterfaces);
  const std::string given = config.get(keys::kConfig);
  const int domain = static_cast<int>(config.get(keys::kDomain));
  const bool loop_named = !named.empty() && std::all_of(named.begin(), named.end(), is_loopback);
  const auto is_named = [&](const std::string& i) {
    return std::find(named.begin(), named.end(), i) != named.end();
  };

  // A user's configuration, resolved as Cyclone resolves it (cyclone_config.hpp).
  const auto checked = [&](const std::string& uri, const std::string& source) {
    const CycloneConfig resolved = resolve_cyclone_config(uri, source);
    const NetworkSelection sel = network_selection(resolved, domain);
    if (!sel.unprovable.empty() && named.empty())
      refuse_transport(
          source + " has settings the loopback check cannot prove stay on this machine: " +
          join(sel.unprovable) + "; remove them, or name the interfaces in dds.interfaces");
    if (!sel.selects_for_domain)
      refuse_transport(
          source + " selects no network interface for DDS domain " + std::to_string(domain) +
          ", so Cyclone would choose one itself (with multicast); name them (e.g. "
          "<NetworkInterface name=\"lo\"/>) or remove it to get Flipper's loopback-only "
          "default");
    Transport t;
    for (const auto& i : sel.interfaces)
      if (std::find(t.interfaces.begin(), t.interfaces.end(), i) == t.interfaces.end())
        t.interfaces.push_back(i);
    const bool peers_local = std::all_of(sel.peers.begin(), sel.peers.end(), loopback_address);
    t.loopback_only = std::all_of(t.interfaces.begin(), t.interfaces.end(), is_loopback) &&
                      peers_local && sel.unprovable.empty();
    for (const auto& i : t.interfaces)
      if (!is_loopback(i) && !is_named(i))
        refuse_transport(
            source + " selects interface '" + i +
            "', which is not loopback; Flipper stays on loopback unless dds.interfaces "
            "names every interface explicitly (dds.interfaces: [" +
            join(named) + "])");
    if (!peers_local && named.empty())
      refuse_transport(
          source +
          " lists discovery peers off loopback; name the interfaces in dds.interfaces to "
          "allow that");
    t.xml = resolved.text();
    t.source = source;
    return t;
  };

  if (!given.empty()) return checked(given, std::string(keys::kConfig.name));
  if (named.empty() || loop_named) {
    if (env_uri != nullptr && *env_uri != '\0') return checked(env_uri, "CYCLONEDDS_URI");
    Transport t;
    t.xml = loopback_xml();
    t.interfaces = {"lo"};
    t.source = "generated loopback configuration";
    return t;
  }
  Transport t;
  t.xml = interfaces_xml(named);
  t.interfaces = named;
  t.loopback_only = false;
  t.source = "generated from dds.interfaces";
  return t;
}

}  // namespace flipper::dds

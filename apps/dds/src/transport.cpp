// The loopback rule for Cyclone DDS (transport.hpp). Cyclone's config is XML; the checks below
// read only the elements that choose the network (interfaces, peers), which is all the rule needs.
#include "flipper/dds/transport.hpp"

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>

#include "flipper/kernel/config.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::dds {
namespace {

[[noreturn]] void refuse(const std::string& message) {
  throw sdk::Error(sdk::codes::kBadConfig, message);
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// CYCLONEDDS_URI may be XML or a (list of) file:// URIs / paths.
std::string uri_text(const std::string& uri) {
  if (uri.find('<') != std::string::npos) return uri;
  std::string text;
  std::stringstream list(uri);
  std::string item;
  while (std::getline(list, item, ',')) {
    std::string path = item.rfind("file://", 0) == 0 ? item.substr(7) : item;
    std::ifstream in(path);
    if (!in) refuse("CYCLONEDDS_URI names '" + item + "', which cannot be read");
    std::ostringstream s;
    s << in.rdbuf();
    text += s.str();
  }
  return text;
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

std::vector<std::string> selected_interfaces(const std::string& xml) {
  std::vector<std::string> out;
  static const std::regex element(R"(<NetworkInterface\b([^>]*)>)", std::regex::icase);
  static const std::regex attribute(R"(\b(name|address)\s*=\s*["']([^"']*)["'])",
                                    std::regex::icase);
  static const std::regex old_style(R"(<NetworkInterfaceAddress>\s*([^<]*?)\s*<)",
                                    std::regex::icase);
  for (std::sregex_iterator it(xml.begin(), xml.end(), element), end; it != end; ++it) {
    const std::string attrs = (*it)[1];
    bool any = false;
    for (std::sregex_iterator a(attrs.begin(), attrs.end(), attribute); a != end; ++a) {
      out.push_back((*a)[2]);
      any = true;
    }
    if (!any) out.push_back("(unnamed interface)");
  }
  for (std::sregex_iterator it(xml.begin(), xml.end(), old_style), end; it != end; ++it) {
    std::stringstream list((*it)[1].str());
    std::string item;
    while (std::getline(list, item, ','))
      if (!item.empty()) out.push_back(item);
  }
  return out;
}

bool is_loopback(const std::string& i) {
  return i == "lo" || i == "loopback" || i == "localhost" || i == "::1" || i.rfind("127.", 0) == 0;
}

bool peers_on_loopback(const std::string& xml) {
  static const std::regex peer(R"(<Peer\b[^>]*\baddress\s*=\s*["']([^"']*)["'])",
                               std::regex::icase);
  for (std::sregex_iterator it(xml.begin(), xml.end(), peer), end; it != end; ++it) {
    std::string address = (*it)[1];
    if (const auto colon = address.rfind(':');
        colon != std::string::npos && address.find(':') == colon)
      address = address.substr(0, colon);  // host:port
    if (!is_loopback(address)) return false;
  }
  return true;
}

std::string Transport::describe(int domain) const {
  return "DDS domain " + std::to_string(domain) + ": interfaces " + join(interfaces) +
         (loopback_only ? " (loopback only; " : " (NOT loopback: named in dds.interfaces; ") +
         source + ")";
}

Transport choose_transport(const kernel::Config& config, const char* env_uri) {
  const std::vector<std::string> named = config.get_string_list("dds.interfaces");
  const std::string given = config.get_string("dds.config");
  const bool loop_named = !named.empty() && std::all_of(named.begin(), named.end(), is_loopback);

  const auto checked = [&](std::string xml, const std::string& source) {
    Transport t;
    t.interfaces = selected_interfaces(xml);
    if (t.interfaces.empty())
      refuse(source +
             " selects no network interface, so Cyclone would use any interface with "
             "multicast; name them (e.g. <NetworkInterface name=\"lo\"/>) or remove it "
             "to get Flipper's loopback-only default");
    t.loopback_only = std::all_of(t.interfaces.begin(), t.interfaces.end(), is_loopback) &&
                      peers_on_loopback(xml);
    if (!t.loopback_only) {
      for (const auto& i : t.interfaces)
        if (!is_loopback(i) && std::find(named.begin(), named.end(), i) == named.end())
          refuse(source + " selects interface '" + i +
                 "', which is not loopback; Flipper stays on loopback unless dds.interfaces "
                 "names every interface explicitly (dds.interfaces: [" +
                 join(named) + "])");
      if (!peers_on_loopback(xml) && named.empty())
        refuse(source +
               " lists discovery peers off loopback; name the interfaces in "
               "dds.interfaces to allow that");
    }
    t.xml = std::move(xml);
    t.source = source;
    return t;
  };

  if (!given.empty()) return checked(given, "dds.config");
  if (named.empty() || loop_named) {
    if (env_uri != nullptr && *env_uri != '\0') return checked(uri_text(env_uri), "CYCLONEDDS_URI");
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

// A Cyclone configuration resolved as Cyclone 0.10.2 resolves it (cyclone_config.hpp). The item
// loop mirrors Cyclone's config loader; the XML goes through Cyclone's own parser.
#include "flipper/dds/cyclone_config.hpp"

#include <arpa/inet.h>
#include <dds/ddsrt/xmlparser.h>
#include <strings.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::dds {
namespace {

[[noreturn]] void refuse_config(const std::string& message) {
  throw sdk::Error(sdk::codes::kBadConfig, message);
}

bool same(const std::string& a, const char* b) {
  return strcasecmp(a.c_str(), b) == 0;
}

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// Builds XmlElements from the parser's callbacks; the parser hands back `eleminfo` values, which
// index `open` (0 = the document).
struct TreeBuilder {
  std::vector<XmlElement> roots;
  std::vector<XmlElement*> open;  // open[i - 1] is eleminfo i
  std::string error;

  static int on_open(void* self, uintptr_t parent, uintptr_t* info, const char* name, int) {
    auto& b = *static_cast<TreeBuilder*>(self);
    std::vector<XmlElement>& siblings = parent == 0 ? b.roots : b.open[parent - 1]->children;
    siblings.push_back(XmlElement{name, {}, {}, {}});
    // Pointers into `siblings` stay valid: an element's siblings grow only after it closes.
    b.open.push_back(&siblings.back());
    *info = b.open.size();
    return 0;
  }
  static int on_attr(void* self, uintptr_t info, const char* name, const char* value, int) {
    static_cast<TreeBuilder*>(self)->open[info - 1]->attributes.emplace_back(name, value);
    return 0;
  }
  static int on_data(void* self, uintptr_t info, const char* data, int) {
    if (info != 0) static_cast<TreeBuilder*>(self)->open[info - 1]->text += data;
    return 0;
  }
  static int on_close(void* self, uintptr_t info, int) {
    auto& b = *static_cast<TreeBuilder*>(self);
    b.open.resize(info - 1);
    return 0;
  }
  static void on_error(void* self, const char* msg, int line) {
    static_cast<TreeBuilder*>(self)->error =
        std::string(msg) + " (line " + std::to_string(line) + ")";
  }
};

struct Parsed {
  std::vector<XmlElement> roots;
  std::size_t consumed = 0;  // bytes of the input the parser used
};

// One top-level element from the start of `xml`, as Cyclone parses an XML item.
Parsed parse_element(const std::string& xml, const std::string& where) {
  TreeBuilder b;
  const ddsrt_xmlp_callbacks cb{&TreeBuilder::on_open, &TreeBuilder::on_attr, &TreeBuilder::on_data,
                                &TreeBuilder::on_close, &TreeBuilder::on_error};
  std::unique_ptr<ddsrt_xmlp_state, void (*)(ddsrt_xmlp_state*)> st(
      ddsrt_xmlp_new_string(xml.c_str(), &b, &cb), &ddsrt_xmlp_free);
  if (!st) refuse_config(where + ": cannot set up the XML parser");
  ddsrt_xmlp_set_options(st.get(),
                         DDSRT_XMLP_ANONYMOUS_CLOSE_TAG | DDSRT_XMLP_MISSING_CLOSE_AS_EOF);
  if (ddsrt_xmlp_parse(st.get()) != 0 || !b.error.empty())
    refuse_config(where + " is not a configuration Cyclone DDS can read: " +
                  (b.error.empty() ? std::string("XML error") : b.error));
  Parsed p;
  p.roots = std::move(b.roots);
  p.consumed = ddsrt_xmlp_get_bufpos(st.get());
  if (p.consumed == 0 || p.consumed > xml.size())
    refuse_config(where + ": the XML parser stopped early");
  return p;
}

std::size_t skip_separators(const std::string& s, std::size_t at) {
  while (at < s.size() && (std::isspace(static_cast<unsigned char>(s[at])) || s[at] == ',')) ++at;
  return at;
}

std::string read_file(const std::string& path, const std::string& item, const std::string& source) {
  std::ifstream in(path, std::ios::binary);
  if (!in) refuse_config(source + " names '" + item + "', which cannot be read");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

bool loopback_address(std::string a) {
  if (a.size() > 2 && a.front() == '[' && a.back() == ']') a = a.substr(1, a.size() - 2);
  in_addr v4{};
  if (inet_pton(AF_INET, a.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  return inet_pton(AF_INET6, a.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

namespace {

// A peer locator's host: "udp/127.0.0.1:7410", "127.0.0.1:7410", "[::1]:7410", "::1".
std::string peer_host(std::string address) {
  if (const auto slash = address.find('/'); slash != std::string::npos)
    address = address.substr(slash + 1);
  if (!address.empty() && address.front() == '[') {
    const auto close = address.find(']');
    return close == std::string::npos ? address : address.substr(0, close + 1);
  }
  const auto colon = address.rfind(':');
  if (colon != std::string::npos && address.find(':') == colon) return address.substr(0, colon);
  return address;
}

std::vector<std::string> comma_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');)
    if (!trimmed(item).empty()) out.push_back(trimmed(item));
  return out;
}

bool domain_applies(const XmlElement& domain, int id) {
  const std::string* attr = domain.attribute("Id");
  if (attr == nullptr || same(trimmed(*attr), "any")) return true;
  char* end = nullptr;
  const long v = std::strtol(attr->c_str(), &end, 10);
  return end != attr->c_str() && trimmed(end).empty() && v == id;
}

struct Walker {
  int domain;
  NetworkSelection out;

  void interface(const std::string& value, bool applies) {
    out.interfaces.push_back(value);
    if (applies) out.selects_for_domain = true;
  }
  void unprovable(const std::string& what) { out.unprovable.push_back(what); }

  void walk(const XmlElement& e, bool applies) {
    const std::string& n = e.name;
    if (same(n, "Domain")) applies = domain_applies(e, domain);
    if (same(n, "NetworkInterface")) {
      const std::string* autodetermine = e.attribute("autodetermine");
      if (autodetermine != nullptr && !same(trimmed(*autodetermine), "false"))
        unprovable("<NetworkInterface autodetermine=\"" + *autodetermine + "\"> (Cyclone chooses)");
      const std::string* name = e.attribute("name");
      const std::string* address = e.attribute("address");
      if (name != nullptr && !name->empty()) interface(*name, applies);
      if (address != nullptr && !address->empty()) interface(*address, applies);
      if ((name == nullptr || name->empty()) && (address == nullptr || address->empty()))
        unprovable("a <NetworkInterface> with neither name nor address");
    } else if (same(n, "NetworkInterfaceAddress")) {
      for (const auto& i : comma_list(e.text)) {
        if (same(i, "auto"))
          unprovable("<NetworkInterfaceAddress>auto</> (Cyclone chooses)");
        else
          interface(i, applies);
      }
    } else if (same(n, "Peer")) {
      const std::string* address = e.attribute("address");
      if (address == nullptr)
        unprovable("a <Peer> without an address");
      else
        out.peers.push_back(peer_host(trimmed(*address)));
    } else if (same(n, "Transport")) {
      const std::string t = trimmed(e.text);
      if (!same(t, "default") && !same(t, "udp") && !same(t, "udp6"))
        unprovable("<Transport>" + t + "</Transport> (only udp is checked)");
    } else if (same(n, "ExternalNetworkAddress")) {
      const std::string a = trimmed(e.text);
      if (!same(a, "auto") && !loopback_address(a))
        unprovable("<ExternalNetworkAddress>" + a + "</ExternalNetworkAddress>");
    } else if (same(n, "MulticastRecvNetworkInterfaceAddresses")) {
      const std::string a = trimmed(e.text);
      const auto list = comma_list(a);
      if (!same(a, "preferred") && !same(a, "none") &&
          !std::all_of(list.begin(), list.end(), loopback_address))
        unprovable("<MulticastRecvNetworkInterfaceAddresses>" + a +
                   "</MulticastRecvNetworkInterfaceAddresses>");
    } else if (same(n, "NetworkPartition")) {
      const std::string* address = e.attribute("Address");
      const auto list = address == nullptr ? std::vector<std::string>{} : comma_list(*address);
      if (list.empty() || !std::all_of(list.begin(), list.end(), loopback_address))
        unprovable("a <NetworkPartition> sending to " +
                   (address == nullptr ? std::string("(no address)") : *address));
    }
    for (const auto& c : e.children) walk(c, applies);
  }
};

}  // namespace

const std::string* XmlElement::attribute(const std::string& attr) const {
  for (const auto& [k, v] : attributes)
    if (same(k, attr.c_str())) return &v;
  return nullptr;
}

std::string CycloneConfig::text() const {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ",") + item;
  return out;
}

CycloneConfig resolve_cyclone_config(const std::string& uri, const std::string& source) {
  CycloneConfig config;
  const auto add_xml = [&](const std::string& xml, const std::string& where, bool whole) {
    // An XML item holds one top-level element; a file may hold several (Cyclone reads them all
    // when its content is handed over as a string), and nothing else.
    std::size_t at = skip_separators(xml, 0);
    do {
      if (at >= xml.size() || xml[at] != '<')
        refuse_config(where + " holds text outside an XML element ('" + xml.substr(at, 24) +
                      "'), which Cyclone would read as another item");
      Parsed p = parse_element(xml.substr(at), where);
      config.items.push_back(xml.substr(at, p.consumed));
      for (auto& r : p.roots) config.roots.push_back(std::move(r));
      at += p.consumed;
      while (at < xml.size() && std::isspace(static_cast<unsigned char>(xml[at]))) ++at;
    } while (whole && at < xml.size());
    return at;
  };
  std::size_t cursor = skip_separators(uri, 0);
  while (cursor < uri.size()) {
    const std::string where = source + " (item at byte " + std::to_string(cursor) + ")";
    if (uri[cursor] == '<') {
      cursor += add_xml(uri.substr(cursor), where, false);
    } else {
      const auto comma = uri.find(',', cursor);
      const std::string item = trimmed(
          uri.substr(cursor, comma == std::string::npos ? std::string::npos : comma - cursor));
      cursor = comma == std::string::npos ? uri.size() : comma;
      const std::string path = item.rfind("file://", 0) == 0 ? item.substr(7) : item;
      add_xml(read_file(path, item, source), source + " file '" + path + "'", true);
    }
    cursor = skip_separators(uri, cursor);
  }
  if (config.items.empty()) refuse_config(source + " is empty");
  return config;
}

NetworkSelection network_selection(const CycloneConfig& config, int domain) {
  Walker w{domain, {}};
  for (const auto& root : config.roots) w.walk(root, true);
  return w.out;
}

}  // namespace flipper::dds

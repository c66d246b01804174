// The loopback rule (apps/dds/transport.hpp, cyclone_config.hpp): no participant unless the
// Cyclone config, resolved as Cyclone resolves it, is loopback only, or the Flipper config names
// the interfaces. Each way around the check that Cyclone 0.10.2 would honour is a case below
// (what Cyclone does with each was read from its own `config` trace, docs/ros2.md). No participant
// is created here except in the last two cases.
#include <fstream>

#include "dds_test_support.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/sdk/errors.hpp"
#include "product_schema.hpp"

using namespace flipper;
using namespace flipper::ddstest;

namespace {
kernel::Config config(std::vector<std::string> sets) {
  return kernel::Config::load(std::nullopt, sets);
}
dds::Transport from_env(const std::string& uri, std::vector<std::string> sets = {}) {
  return dds::choose_transport(config(std::move(sets)), uri.c_str());
}
const char* kEth0 =
    "<CycloneDDS><Domain><General><Interfaces><NetworkInterface name=\"eth0\"/></Interfaces>"
    "</General></Domain></CycloneDDS>";
const std::string kLo =
    "<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/>"
    "</Interfaces></General></Domain></CycloneDDS>";

std::string write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path.string();
}
}  // namespace

TEST_CASE("the default transport is the generated loopback configuration", "[dds]") {
  const dds::Transport t = dds::choose_transport(config({}), nullptr);
  CHECK(t.loopback_only);
  CHECK(t.interfaces == std::vector<std::string>{"lo"});
  CHECK(t.xml == dds::loopback_xml());
  const auto sel = dds::network_selection(dds::resolve_cyclone_config(t.xml, "t"), 0);
  CHECK(sel.interfaces == std::vector<std::string>{"lo"});
  CHECK(sel.peers == std::vector<std::string>{"127.0.0.1"});
  CHECK(sel.unprovable.empty());
  CHECK(t.describe(3) ==
        "DDS domain 3: interfaces lo (loopback only; generated loopback configuration)");
}

TEST_CASE("a loopback CYCLONEDDS_URI is used, anything else refused", "[dds]") {
  const dds::Transport t = from_env(dds::loopback_xml());
  CHECK(t.source == "CYCLONEDDS_URI");
  CHECK(t.loopback_only);
  CHECK_THROWS_WITH(from_env(kEth0), Catch::Contains("interface 'eth0', which is not loopback"));
  CHECK_THROWS_WITH(from_env("<CycloneDDS/>"), Catch::Contains("selects no network interface"));
  const std::string far_peer =
      "<CycloneDDS><Domain><General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
      "</General><Discovery><Peers><Peer address=\"10.0.0.7\"/></Peers></Discovery></Domain>"
      "</CycloneDDS>";
  CHECK_THROWS_WITH(from_env(far_peer), Catch::Contains("peers off loopback"));
  // A name is not an address: "localhost" could resolve anywhere.
  const std::string named_peer = kLo.substr(0, kLo.size() - 22) +
                                 "<Discovery><Peers><Peer address=\"localhost:7410\"/></Peers>"
                                 "</Discovery></Domain></CycloneDDS>";
  CHECK_THROWS_WITH(from_env(named_peer), Catch::Contains("peers off loopback"));
}

TEST_CASE("every item of a comma-separated configuration is checked", "[dds]") {
  const auto dir = scratch_dir("items");
  const std::string eth = write_file(dir / "eth.xml", kEth0);
  const std::string lo = write_file(dir / "lo.xml", kLo);
  // Cyclone loads all of these (its trace lists eth0 from item {1}): each is refused.
  CHECK_THROWS_WITH(from_env(kLo + ",file://" + eth), Catch::Contains("'eth0'"));
  CHECK_THROWS_WITH(from_env(kLo + "," + eth), Catch::Contains("'eth0'"));
  CHECK_THROWS_WITH(from_env(kLo + " , " + kEth0), Catch::Contains("'eth0'"));
  CHECK_THROWS_WITH(from_env(kLo + kEth0), Catch::Contains("'eth0'"));  // no separator at all
  CHECK_THROWS_WITH(from_env("file://" + lo + ",file://" + eth), Catch::Contains("'eth0'"));
  // A file that goes on after its element would hand Cyclone another item: refused.
  const std::string chained = write_file(dir / "chained.xml", kLo + ",file://" + eth);
  CHECK_THROWS_WITH(from_env("file://" + chained), Catch::Contains("outside an XML element"));
  CHECK_THROWS_WITH(from_env("file://" + (dir / "missing.xml").string()),
                    Catch::Contains("cannot be read"));
  // A loopback file is accepted, and Cyclone gets its content, not its name: the file it reads
  // is the file that was checked.
  const dds::Transport t = from_env("file://" + lo);
  CHECK(t.loopback_only);
  CHECK(t.xml == kLo);
  CHECK(from_env(lo).xml == kLo);
  std::filesystem::remove_all(dir);
}

TEST_CASE("XML is read as Cyclone reads it: comments, case, domains, anonymous close tags",
          "[dds]") {
  // lo inside a comment selects nothing: Cyclone would choose an interface itself.
  CHECK_THROWS_WITH(
      from_env("<CycloneDDS><Domain Id=\"any\"><!-- <General><Interfaces><NetworkInterface "
               "name=\"lo\"/></Interfaces></General> --></Domain></CycloneDDS>"),
      Catch::Contains("selects no network interface"));
  // Element and attribute names in any case (Cyclone matches them without case).
  CHECK_THROWS_WITH(from_env("<cyclonedds><domain><general><interfaces><networkinterface "
                             "NAME=\"eth9\"/></interfaces></general></domain></cyclonedds>"),
                    Catch::Contains("'eth9'"));
  // lo for another domain only: domain 0 would get Cyclone's own choice.
  CHECK_THROWS_WITH(from_env("<CycloneDDS><Domain Id=\"9\"><General><Interfaces><NetworkInterface "
                             "name=\"lo\"/></Interfaces></General></Domain></CycloneDDS>"),
                    Catch::Contains("selects no network interface for DDS domain 0"));
  // ... but lo for this domain, written as Cyclone accepts it, counts.
  CHECK(from_env("<CycloneDDS><Domain Id=\"07\"><General><Interfaces><NetworkInterface "
                 "name=\"lo\"/></></></></>",
                 {"dds.domain=7"})
            .loopback_only);
  // An interface for another domain id is still looked at (refused, not trusted).
  CHECK_THROWS_WITH(from_env(kLo + "<CycloneDDS><Domain Id=\"9\"><General><Interfaces>"
                                   "<NetworkInterface name=\"eth9\"/></Interfaces></General>"
                                   "</Domain></CycloneDDS>"),
                    Catch::Contains("'eth9'"));
  // A section outside Domain (Cyclone moves it into Domain) and a bare fragment count too.
  CHECK_THROWS_WITH(from_env("<CycloneDDS><General><Interfaces><NetworkInterface name=\"eth9\"/>"
                             "</Interfaces></General></CycloneDDS>"),
                    Catch::Contains("'eth9'"));
  CHECK(from_env("<General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces></General>")
            .loopback_only);
  CHECK_THROWS_WITH(from_env("<CycloneDDS><Domain><General><Interfaces>"),
                    Catch::Contains("selects no network interface"));
  CHECK_THROWS_WITH(from_env("<CycloneDDS><Domain></General></CycloneDDS>"),
                    Catch::Contains("not a configuration Cyclone DDS can read"));
}

TEST_CASE("settings that choose the network by themselves are refused", "[dds]") {
  const auto with = [](const std::string& general) {
    return "<CycloneDDS><Domain><General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>" +
           general + "</General></Domain></CycloneDDS>";
  };
  CHECK_THROWS_WITH(from_env("<CycloneDDS><Domain><General><Interfaces><NetworkInterface "
                             "name=\"lo\" autodetermine=\"true\"/></Interfaces></General>"
                             "</Domain></CycloneDDS>"),
                    Catch::Contains("autodetermine"));
  CHECK_THROWS_WITH(from_env("<General><NetworkInterfaceAddress>auto</NetworkInterfaceAddress>"
                             "</General>"),
                    Catch::Contains("Cyclone chooses"));
  CHECK_THROWS_WITH(from_env(with("<Transport>tcp</Transport>")), Catch::Contains("Transport"));
  CHECK_THROWS_WITH(from_env(with("<ExternalNetworkAddress>192.0.2.7</ExternalNetworkAddress>")),
                    Catch::Contains("ExternalNetworkAddress"));
  CHECK_THROWS_WITH(from_env(with("<MulticastRecvNetworkInterfaceAddresses>all"
                                  "</MulticastRecvNetworkInterfaceAddresses>")),
                    Catch::Contains("MulticastRecvNetworkInterfaceAddresses"));
  CHECK_THROWS_WITH(from_env(with("<NetworkInterface name=\"lo${X}\"/>")),
                    Catch::Contains("'lo${X}'"));  // Cyclone expands ${X}; not provable
  CHECK(from_env(with("<Transport>udp</Transport><MulticastRecvNetworkInterfaceAddresses>"
                      "preferred</MulticastRecvNetworkInterfaceAddresses>"))
            .loopback_only);
}

TEST_CASE("interfaces named in dds.interfaces are the explicit way off loopback", "[dds]") {
  const dds::Transport t = dds::choose_transport(config({"dds.interfaces=[eth0]"}), nullptr);
  CHECK_FALSE(t.loopback_only);
  CHECK(t.interfaces == std::vector<std::string>{"eth0"});
  CHECK(dds::network_selection(dds::resolve_cyclone_config(t.xml, "t"), 0).interfaces ==
        std::vector<std::string>{"eth0"});
  // A dds.config selecting eth0 is allowed only when dds.interfaces names it.
  CHECK_THROWS_WITH(dds::choose_transport(config({std::string("dds.config=") + kEth0}), nullptr),
                    Catch::Contains("not loopback"));
  CHECK_NOTHROW(dds::choose_transport(
      config({std::string("dds.config=") + kEth0, "dds.interfaces=[eth0]"}), nullptr));
}

TEST_CASE("flipper session refuses a non-loopback DDS config with exit 2", "[dds]") {
  const auto dir = scratch_dir("refuse");
  const std::string eth = write_file(dir / "eth.xml", kEth0);
  for (const std::string& cfg : {std::string(kEth0), kLo + ",file://" + eth}) {
    INFO(cfg);
    // Its error output too (any misuse exits 2: the code and the reason are what is checked).
    testsupport::ChildProcess p({"/bin/sh", "-c", "exec \"$0\" \"$@\" 2>&1", flipper_bin(),
                                 "session", "--set", "publish.plans=dds", "--set",
                                 "dds.config=" + cfg, "--set", "lexicon.path=:memory:"});
    const std::string out = p.read_all();
    CHECK(p.finish() == 2);
    CHECK(out ==
          "flipper session: [bad_config] dds.config selects interface 'eth0', which is not "
          "loopback; Flipper stays on loopback unless dds.interfaces names every interface "
          "explicitly (dds.interfaces: [])\n");
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("replication needs a site name, world.resolution must be positive", "[dds]") {
  CHECK_THROWS_WITH(config({"world.resolution=0"}),
                    "config <embedded default>: config key 'world.resolution' = 0 is out of range "
                    "[0.001, 1000]");
  CHECK_THROWS_WITH(config({"world.origin=[a, 1]"}), Catch::Contains("list of numbers"));
  testsupport::ChildProcess p({ddstest::flipper_bin(), "session", "--set",
                               "lexicon.replication=dds", "--set", "lexicon.path=:memory:"});
  CHECK(p.finish() == 2);
}

TEST_CASE("dds.namespace must be a ROS 2 name token", "[dds]") {
  for (const char* bad : {"1robot", "robot/one", "robot-1", "a b"}) {
    INFO(bad);
    testsupport::ChildProcess p({flipper_bin(), "session", "--set", "publish.plans=dds", "--set",
                                 std::string("dds.namespace=") + bad, "--set",
                                 "lexicon.path=:memory:"});
    CHECK(p.finish() == 2);
  }
}

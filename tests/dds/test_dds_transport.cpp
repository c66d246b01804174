// The loopback rule (apps/dds/transport.hpp): no participant unless the Cyclone config is
// loopback only or the Flipper config names the interfaces. No participant is created here.
#include "dds_test_support.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/sdk/errors.hpp"

using namespace flipper;

namespace {
kernel::Config config(std::vector<std::string> sets) {
  return kernel::Config::load(std::nullopt, sets);
}
const char* kEth0 =
    "<CycloneDDS><Domain><General><Interfaces><NetworkInterface name=\"eth0\"/></Interfaces>"
    "</General></Domain></CycloneDDS>";
}  // namespace

TEST_CASE("the default transport is the generated loopback configuration", "[dds]") {
  const dds::Transport t = dds::choose_transport(config({}), nullptr);
  CHECK(t.loopback_only);
  CHECK(t.interfaces == std::vector<std::string>{"lo"});
  CHECK(t.xml == dds::loopback_xml());
  CHECK(dds::selected_interfaces(t.xml) == std::vector<std::string>{"lo"});
  CHECK(dds::peers_on_loopback(t.xml));
  CHECK(t.describe(3) ==
        "DDS domain 3: interfaces lo (loopback only; generated loopback configuration)");
}

TEST_CASE("a loopback CYCLONEDDS_URI is used, anything else refused", "[dds]") {
  const dds::Transport t = dds::choose_transport(config({}), dds::loopback_xml().c_str());
  CHECK(t.source == "CYCLONEDDS_URI");
  CHECK_THROWS_WITH(dds::choose_transport(config({}), kEth0),
                    Catch::Contains("interface 'eth0', which is not loopback"));
  CHECK_THROWS_WITH(dds::choose_transport(config({}), "<CycloneDDS/>"),
                    Catch::Contains("selects no network interface"));
  const std::string far_peer =
      "<CycloneDDS><Domain><General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
      "</General><Discovery><Peers><Peer address=\"10.0.0.7\"/></Peers></Discovery></Domain>"
      "</CycloneDDS>";
  CHECK_THROWS_WITH(dds::choose_transport(config({}), far_peer.c_str()),
                    Catch::Contains("peers off loopback"));
}

TEST_CASE("interfaces named in dds.interfaces are the explicit way off loopback", "[dds]") {
  const dds::Transport t = dds::choose_transport(config({"dds.interfaces=[eth0]"}), nullptr);
  CHECK_FALSE(t.loopback_only);
  CHECK(t.interfaces == std::vector<std::string>{"eth0"});
  CHECK(dds::selected_interfaces(t.xml) == std::vector<std::string>{"eth0"});
  // A dds.config selecting eth0 is allowed only when dds.interfaces names it.
  CHECK_THROWS_WITH(dds::choose_transport(config({std::string("dds.config=") + kEth0}), nullptr),
                    Catch::Contains("not loopback"));
  CHECK_NOTHROW(dds::choose_transport(
      config({std::string("dds.config=") + kEth0, "dds.interfaces=[eth0]"}), nullptr));
}

TEST_CASE("flipper session refuses a non-loopback DDS config with exit 2", "[dds]") {
  testsupport::ChildProcess p({ddstest::flipper_bin(), "session", "--set", "publish.plans=dds",
                               "--set", std::string("dds.config=") + kEth0, "--set",
                               "lexicon.path=:memory:"});
  CHECK(p.finish() == 2);
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

// bench_dds: (1) replication latency between two sites — site A commits a definition and
// publishes it, site B applies it (induction + durable commit) and can parse with it; p50/p99
// over N definitions, target p99 <= 1000 ms ("usable within 1 s"); (2) plan publication
// overhead per accept — the PlanPublisher call alone, and accept with vs without it.
// Two sites in one process (two participants on one loopback domain, each its own store in a
// temp dir); the domain is claimed like the DDS tests' (tests/support/dds_domain.hpp), so runs
// from other checkouts do not meet.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <thread>
#include <vector>

#include "dds_domain.hpp"
#include "flipper/dds/lexicon_replicator.hpp"
#include "flipper/dds/plan_publisher.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/wiring/session_factory.hpp"

using namespace flipper;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double pct(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

wiring::SessionHost host(const std::filesystem::path& store, const std::string& site) {
  return wiring::open_host(std::nullopt, {"lexicon.path=" + store.string(), "rewriter=null",
                                          "lexicon.replication=dds", "lexicon.site=" + site});
}

std::shared_ptr<dds::Participant> participant(int domain, std::ostream& log) {
  dds::Transport t;
  t.xml = dds::loopback_xml();
  t.interfaces = {"lo"};
  t.source = "bench";
  return std::make_shared<dds::Participant>(domain, t, log);
}

}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 200;
  const int domain = flipper::testsupport::claimed_dds_domain();
  const auto dir =
      std::filesystem::temp_directory_path() / ("flipper-bench-dds-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ostringstream quiet;

  // (1) Replication latency.
  {
    wiring::SessionHost ha = host(dir / "a.sqlite", "a"), hb = host(dir / "b.sqlite", "b");
    auto pa = participant(domain, quiet), pb = participant(domain, quiet);
    auto ra = dds::LexiconReplicator::start(pa, ha, quiet);
    auto rb = dds::LexiconReplicator::start(pb, hb, quiet);
    auto sa = ha.open();
    ra->attach(*sa);
    sa->handle_line(R"({"op":"user","name":"ana"})");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // discovery
    std::vector<double> latency, define_ms;
    for (int i = 0; i < n; ++i) {
      const std::uint64_t before = rb->applied();
      const std::string line = R"({"op":"define","head":"chore )" + std::to_string(i) +
                               R"( now","body":["move left","move up"]})";
      const auto t_define = Clock::now();
      const std::string answer = sa->handle_line(line);
      define_ms.push_back(ms_since(t_define));
      const auto t0 = Clock::now();  // published: the define op has returned
      while (rb->applied() == before && ms_since(t0) < 10000)
        std::this_thread::sleep_for(std::chrono::microseconds(50));
      latency.push_back(ms_since(t0));
      if (answer.find("\"ok\":true") == std::string::npos) {
        std::cerr << "bench_dds: define failed: " << answer << "\n";
        return 1;
      }
    }
    std::printf("replication, %d definitions A -> B (B: induction + durable commit)\n", n);
    std::printf(
        "  latency publish -> applied at B   p50 %8.2f ms   p99 %8.2f ms   (target p99 <= 1000 "
        "ms)\n",
        pct(latency, 0.5), pct(latency, 0.99));
    std::printf("  define at A (with publication)    p50 %8.2f ms   p99 %8.2f ms\n",
                pct(define_ms, 0.5), pct(define_ms, 0.99));
  }

  // (2) Plan publication overhead per accept.
  {
    wiring::SessionHost h = wiring::open_host(std::nullopt, {"lexicon.path=:memory:"});
    auto p = participant(domain, quiet);
    auto publisher =
        std::make_shared<dds::PlanPublisher>(p, dds::PlanFrame::from_config(h.runtime->config, 2));
    const auto accept_ms = [&](bool publish) {
      auto s = h.open();
      if (publish) s->install(publisher);
      std::vector<double> v;
      for (int i = 0; i < 300; ++i) {
        s->handle_line(i % 2 ? R"({"op":"query","text":"visit room1"})"
                             : R"({"op":"query","text":"visit room3"})");
        const auto t0 = Clock::now();
        s->handle_line(R"({"op":"accept","rank":0})");
        v.push_back(ms_since(t0));
      }
      return v;
    };
    const auto without = accept_ms(false);
    const auto with = accept_ms(true);
    // The publisher call alone, on the last plan shape (a room-to-room visit).
    auto s = h.open();
    s->handle_line(R"({"op":"query","text":"visit room1"})");
    const auto* q = s->last_query();
    std::vector<double> call_us;
    for (int i = 0; i < 1000; ++i) {
      const auto t0 = Clock::now();
      publisher->publish(
          kernel::PlanAccepted{q->world, q->shown[0].outcome, "visit room1", "bench", 1});
      call_us.push_back(ms_since(t0) * 1000);
    }
    std::printf("plan publication (nav_msgs/Path + ActionList, %zu poses)\n",
                q->shown[0].outcome.trace.size() + 1);
    std::printf(
        "  publisher call                    p50 %8.1f us   p99 %8.1f us   (target p50 <= 100 "
        "us)\n",
        pct(call_us, 0.5), pct(call_us, 0.99));
    std::printf("  accept without / with publishing  p50 %8.3f / %.3f ms\n", pct(without, 0.5),
                pct(with, 0.5));
  }
  std::filesystem::remove_all(dir);
  return 0;
}

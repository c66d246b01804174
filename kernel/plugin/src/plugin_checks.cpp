// Plugin answers checked where they enter the kernel (docs/plugins-untrusted.md): the plugin
// call through its PluginRef, then the SDK's one check of the answer
// (flipper/sdk/answer_check.hpp).
#include "flipper/kernel/plugin_checks.hpp"

#include <cstring>
#include <optional>
#include <string_view>

#include "flipper/kernel/isolation.hpp"
#include "flipper/sdk/answer_check.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"

namespace flipper::kernel {

using sdk::Cell;

namespace {

// Answers as bytes, from an isolated call's child process (isolation.hpp). The reader checks
// every length against what is left: the child is the untrusted plugin's process.
class Bytes {
 public:
  template <class T>
  void put(const T& v) {
    out_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put_text(const std::string& s) {
    put<std::uint64_t>(s.size());
    out_ += s;
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(const PluginId& plugin, const char* op, std::string_view in)
      : plugin_(plugin), op_(op), in_(in) {}
  template <class T>
  T get() {
    T v{};
    need(sizeof v);
    std::memcpy(&v, in_.data(), sizeof v);
    in_.remove_prefix(sizeof v);
    return v;
  }
  std::uint64_t count(std::size_t each) {
    const auto n = get<std::uint64_t>();
    need(n > in_.size() / each ? in_.size() + 1 : n * each);
    return n;
  }
  sdk::PlanStatus status() {
    const auto s = get<sdk::PlanStatus>();
    if (s != sdk::PlanStatus::found && s != sdk::PlanStatus::no_path &&
        s != sdk::PlanStatus::stopped && s != sdk::PlanStatus::invalid)
      malformed();
    return s;
  }
  std::string text() {
    const auto n = count(1);
    std::string s(in_.substr(0, n));
    in_.remove_prefix(n);
    return s;
  }
  void done() const { need_nothing_left(); }

 private:
  const PluginId& plugin_;
  const char* op_;
  std::string_view in_;
  void need(std::size_t n) const {
    if (n > in_.size()) malformed();
  }
  void need_nothing_left() const {
    if (!in_.empty()) malformed();
  }
  [[noreturn]] void malformed() const {
    throw sdk::Error(kPluginCrashed,
                     plugin_.label() + ": " + op_ + ": its process sent a malformed answer");
  }
};

std::string path_bytes(const sdk::PathResult& r) {
  Bytes b;
  b.put(r.status);
  b.put(r.target);
  b.put<std::uint64_t>(r.path.size());
  for (const Cell& c : r.path) b.put(c);
  b.put(r.expansions);
  b.put_text(r.message);
  return b.take();
}

sdk::PathResult path_of(const PluginId& plugin, std::string_view bytes) {
  Reader in(plugin, "plan", bytes);
  sdk::PathResult r;
  r.status = in.status();
  r.target = in.get<Cell>();
  r.path.resize(in.count(sizeof(Cell)));
  for (Cell& c : r.path) c = in.get<Cell>();
  r.expansions = in.get<std::uint64_t>();
  r.message = in.text();
  in.done();
  return r;
}

std::string tour_bytes(const sdk::TourResult& t) {
  Bytes b;
  b.put(t.status);
  b.put<std::uint64_t>(t.order.size());
  for (const std::size_t i : t.order) b.put<std::uint64_t>(i);
  b.put(t.length);
  return b.take();
}

sdk::TourResult tour_of(const PluginId& plugin, std::string_view bytes) {
  Reader in(plugin, "tour", bytes);
  sdk::TourResult t;
  t.status = in.status();
  t.order.resize(in.count(sizeof(std::uint64_t)));
  for (std::size_t& i : t.order) i = static_cast<std::size_t>(in.get<std::uint64_t>());
  t.length = in.get<double>();
  in.done();
  return t;
}

// A planner call as PluginRef::call makes it, in a child process when the ref says so.
template <class Result, class Call, class ToBytes, class FromBytes>
Result planner_call(const PluginRef<const sdk::Planner>& planner, const char* op,
                    const sdk::StopCondition& stop, Call call, ToBytes to_bytes,
                    FromBytes from_bytes) {
  auto in_process = [&] {
    return planner.call(op, [&](const sdk::Planner& p) { return call(p, stop); });
  };
  if (planner.isolation() != Isolation::process) return in_process();
  std::optional<std::string> bytes;
  {
    const detail::CallTimer timer(planner.id(), op);
    const sdk::Planner& object = *planner.borrow();
    bytes = detail::call_in_child(
        planner.id(), op, stop,
        [&](const sdk::StopCondition& child_stop) { return to_bytes(call(object, child_stop)); });
  }
  // No child could be started (descriptors or processes exhausted): in process, as documented.
  return bytes ? from_bytes(planner.id(), *bytes) : in_process();
}

}  // namespace

void throw_invalid_output(const PluginId& plugin, const char* code, const std::string& what) {
  throw sdk::Error(code, plugin.label() + ": " + what);
}

sdk::PathResult checked_plan(const PluginRef<const sdk::Planner>& planner,
                             const sdk::Geometry& geometry, const sdk::PathRequest& request,
                             const sdk::StopCondition& stop) {
  sdk::PathResult r = planner_call<sdk::PathResult>(
      planner, "plan", stop,
      [&](const sdk::Planner& p, const sdk::StopCondition& s) {
        return p.plan(geometry, request, s);
      },
      path_bytes, path_of);
  if (auto v = sdk::path_violation(geometry, request, r))
    throw_invalid_output(planner.id(), sdk::codes::kInvalidPlan, *v);
  return r;
}

sdk::TourResult checked_tour(const PluginRef<const sdk::Planner>& planner,
                             const sdk::Geometry& geometry, Cell start,
                             const std::vector<Cell>& points, const sdk::StopCondition& stop) {
  sdk::TourResult t = planner_call<sdk::TourResult>(
      planner, "tour", stop,
      [&](const sdk::Planner& p, const sdk::StopCondition& s) {
        return p.tour(geometry, start, points, s);
      },
      tour_bytes, tour_of);
  if (auto v = sdk::tour_violation(points.size(), t))
    throw_invalid_output(planner.id(), sdk::codes::kInvalidPlan, *v);
  return t;
}

sdk::ParseResult checked_parse(const PluginRef<const sdk::Parser>& parser,
                               const sdk::ParseRequest& request) {
  sdk::ParseResult r = parser.call("parse", [&](const sdk::Parser& p) { return p.parse(request); });
  if (auto v = sdk::parse_violation(request, r))
    throw_invalid_output(parser.id(), v->code, v->what);
  return r;
}

}  // namespace flipper::kernel

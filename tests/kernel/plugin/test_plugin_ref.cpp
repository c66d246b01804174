// PluginRef: every call into a plugin names a failing plugin the same way, whatever its kind and
// wherever the kernel calls it (runtime start-up, the executor, the session).
#include <nlohmann/json.hpp>
#include <regex>

#include "flipper/kernel/executor.hpp"
#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/kernel/session.hpp"
#include "flipper/sdk/canonical.hpp"
#include "kernel/kernel_test_support.hpp"

using namespace flipper;

namespace {

std::string library(const std::string& name) {
  return kerneltest::good_dir() + "/" + name + ".so";
}

// The one message shape: "plugin 'NAME' (FILE): OP: MESSAGE".
std::string shape(const std::string& name, const std::string& op) {
  return "plugin '" + name + "' (" + library(name) + "): " + op + ": thrown on purpose in " + op;
}

std::string message_of(const std::function<void()>& f, std::string& code) {
  try {
    f();
  } catch (const sdk::Error& e) {
    code = e.code();
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("a throwing plugin gives one message shape for every kind", "[plugin_ref]") {
  struct Case {
    const char* kind;
    const char* op;
  };
  // make_runtime calls world.dims, planner.traits and parser.set_grammar.
  for (const Case c :
       {Case{"world", "dims"}, Case{"planner", "traits"}, Case{"parser", "set_grammar"}}) {
    INFO(c.kind << "." << c.op);
    std::string code;
    const std::string message = message_of(
        [&] {
          (void)kernel::make_runtime(
              kerneltest::test_config({std::string(c.kind) + ".params.throw_in=" + c.op}));
        },
        code);
    CHECK(code == "plugin_error");
    CHECK(message == shape(std::string("test_") + c.kind, c.op));
  }
  // The world plugin loading the default world.
  std::string code;
  std::string message = message_of(
      [] { (void)kernel::make_runtime(kerneltest::test_config({"world.params.throw_in=load"})); },
      code);
  CHECK(code == "plugin_error");
  CHECK(message == shape("test_world", "load"));
  // The scorer, called through the runtime's handle as the session does.
  const auto rt =
      kernel::make_runtime(kerneltest::test_config({"scorer.params.throw_in=save_state"}));
  message = message_of(
      [&] { rt->scorer.call("save_state", [](const sdk::Scorer& s) { return s.save_state(); }); },
      code);
  CHECK(code == "plugin_error");
  CHECK(message == shape("test_scorer", "save_state"));
}

TEST_CASE("a throwing planner is named in the executor's outcome, not blamed on the executor",
          "[plugin_ref]") {
  const auto rt = kernel::make_runtime(kerneltest::test_config({"planner.params.throw_in=plan"}));
  const kernel::Executor exec(rt->planner);
  const sdk::Outcome o = exec.run(sdk::read_canonical("{visit [2,2]}"), rt->default_world);
  REQUIRE(o.error);
  CHECK(o.error_code == std::optional<std::string>("plugin_error"));
  CHECK(*o.error == shape("test_planner", "plan"));
  CHECK(o.world.robot == rt->default_world.robot);
}

TEST_CASE("a throwing parser is named in the session's answer", "[plugin_ref]") {
  std::shared_ptr<kernel::Runtime> rt =
      kernel::make_runtime(kerneltest::test_config({"parser.params.throw_in=parse"}));
  kernel::Session session(rt);
  const kernel::Json a = session.handle(kernel::Json{{"op", "query"}, {"text", "go"}});
  CHECK(a["ok"] == false);
  CHECK(a["error"]["code"] == "plugin_error");
  CHECK(a["error"]["message"] == shape("test_parser", "parse"));
}

TEST_CASE("sdk::Error from a plugin keeps its code and message", "[plugin_ref]") {
  const auto rt = kernel::make_runtime(kerneltest::test_config());
  kerneltest::require_error([&] { (void)kernel::load_world_file(*rt, R"({"bad": 1})"); },
                            "bad_world", {"test world: entry 'bad' is not allowed"});
}

namespace {
int g_calls = 0;
std::string g_last;
void count_call(const kernel::PluginId& id, std::string_view op, const kernel::PluginCallTime&) {
  ++g_calls;
  g_last = id.name + "." + std::string(op);
}
}  // namespace

TEST_CASE("the plugin-call observer sees every call, also failing ones", "[plugin_ref]") {
  const auto rt =
      kernel::make_runtime(kerneltest::test_config({"scorer.params.throw_in=save_state"}));
  g_calls = 0;
  REQUIRE(kernel::set_plugin_call_observer(&count_call) == nullptr);
  (void)rt->world.call("dims", [](const sdk::World& w) { return w.dims(); });
  CHECK(g_calls == 1);
  CHECK(g_last == "test_world.dims");
  CHECK_THROWS(rt->scorer.call("save_state", [](const sdk::Scorer& s) { return s.save_state(); }));
  CHECK(g_calls == 2);
  CHECK(g_last == "test_scorer.save_state");
  CHECK(kernel::set_plugin_call_observer(nullptr) == &count_call);
  (void)rt->world.call("dims", [](const sdk::World& w) { return w.dims(); });
  CHECK(g_calls == 2);
}

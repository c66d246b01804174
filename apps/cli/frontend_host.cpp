// flipper's side of the front-end modules (frontend_module.hpp, flipper/sdk/frontend.hpp): the
// host a front end runs on, `serve`, `dds`, `accounts` and a session's DDS services handed to the
// in-tree modules, and `flipper frontend NAME` for any other front end on the plugin path.
#include <atomic>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "commands.hpp"
#include "common.hpp"
#include "dds_services.hpp"
#include "flipper/kernel/loader.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/frontend.hpp"
#include "flipper/sdk/param_check.hpp"
#include "flipper/wiring/session_factory.hpp"
#include "frontend_module.hpp"

namespace flipper::cli {
namespace {

namespace fs = std::filesystem;

/// <exe>/../lib/flipper/frontends: found relative to the executable only (the install layout,
/// which the build tree mirrors), like the plugins and configs.
std::string frontends_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path dir = ec ? fs::path(".") : exe.parent_path();
  return (dir / ".." / "lib" / "flipper" / "frontends").lexically_normal().string();
}

/// A loaded front end. Modules stay mapped until the process ends (what they started, such as
/// a session's DDS services, may run code of theirs until then).
struct Module {
  kernel::LoadedPlugin plugin;
  std::shared_ptr<sdk::Plugin> object;
  sdk::Frontend* frontend = nullptr;
};

Module load(const kernel::PluginLoader& loader, const std::string& name,
            const std::map<std::string, sdk::ParamValue>& given) {
  Module m;
  m.plugin = loader.open(name, sdk::PluginKind::frontend);
  const sdk::Params params = sdk::validate_params(m.plugin.schema(), given, "frontend." + name);
  m.object = loader.instantiate(m.plugin, params);
  m.frontend = dynamic_cast<sdk::Frontend*>(m.object.get());
  if (m.frontend == nullptr)
    throw sdk::Error(sdk::codes::kPluginLoadFailed,
                     "plugin " + m.plugin.label() + " does not implement the frontend interface");
  static std::vector<std::shared_ptr<void>> kept;  // never unloaded (see Module)
  kept.push_back(m.plugin.library);
  return m;
}

std::atomic<bool> g_stopping{false};
extern "C" void on_stop_signal(int) {
  g_stopping.store(true);
}

/// The host of frontend.hpp. Sessions share one runtime and lexicon (wiring::SessionHost, opened
/// at the first session); requests of all sessions are answered one at a time (plugins serve one
/// request at a time per instance, docs/studio.md).
class ModuleHost final : public sdk::FrontendHost {
 public:
  ModuleHost(std::string command, const CommonOptions* opts, InTreeCall* in_tree)
      : command_(std::move(command)), opts_(opts), in_tree_(in_tree) {}

  SessionId open_session() override {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (opts_ == nullptr) throw sdk::Error(sdk::codes::kBadRequest, "this host has no sessions");
    if (!host_)
      host_ = std::make_unique<wiring::SessionHost>(
          wiring::open_host(config_file(*opts_), opts_->overrides));
    const SessionId id = ++last_id_;
    sessions_.emplace(id, host_->open());
    return id;
  }

  std::string handle(SessionId session, const std::string& request) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto it = sessions_.find(session);
    if (it == sessions_.end())
      throw sdk::Error(sdk::codes::kBadRequest,
                       "there is no session " + std::to_string(session) + " on this host");
    kernel::Session& s = *it->second;
    s.activate();
    if (request.size() > s.options().input.max_line_bytes) return s.line_too_long(request.size());
    return s.handle_line(request);
  }

  void close_session(SessionId session) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    sessions_.erase(session);
  }

  bool stopping() const override { return g_stopping.load(); }

  void log(const std::string& line) override {
    std::cerr << "flipper " << command_ << ": " << line << std::endl;
  }

  void* internals(const char* tag) override {
    return in_tree_ != nullptr && std::string(tag) == kInTreeTag ? in_tree_ : nullptr;
  }

 private:
  std::string command_;
  const CommonOptions* opts_;
  InTreeCall* in_tree_;
  std::mutex mutex_;
  std::unique_ptr<wiring::SessionHost> host_;
  std::map<SessionId, std::unique_ptr<kernel::Session>> sessions_;
  SessionId last_id_ = 0;
};

/// `--param key=value`, typed by the front end's schema.
std::map<std::string, sdk::ParamValue> parse_params(const sdk::ParamSchema& schema,
                                                    const std::vector<std::string>& given,
                                                    const std::string& where) {
  std::map<std::string, sdk::ParamValue> out;
  for (const auto& kv : given) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw sdk::Error(sdk::codes::kBadConfig, "--param '" + kv + "' is not key=value");
    const std::string key = kv.substr(0, eq);
    const std::string text = kv.substr(eq + 1);
    const sdk::ParamSpec* spec = schema.find(key);
    const std::string what = "config key '" + where + "." + key + "' = '" + text + "'";
    try {
      std::size_t used = 0;
      switch (spec == nullptr ? sdk::ParamType::String : spec->type) {
        case sdk::ParamType::Bool:
          if (text != "true" && text != "false") throw std::invalid_argument(text);
          out[key] = text == "true";
          break;
        case sdk::ParamType::Int:
          out[key] = static_cast<std::int64_t>(std::stoll(text, &used));
          if (used != text.size()) throw std::invalid_argument(text);
          break;
        case sdk::ParamType::Double:
          out[key] = std::stod(text, &used);
          if (used != text.size()) throw std::invalid_argument(text);
          break;
        default:
          out[key] = text;  // unknown keys are named by validate_params
      }
    } catch (const std::logic_error&) {
      throw sdk::Error(sdk::codes::kBadConfig, what + " must be " + sdk::type_phrase(spec->type));
    }
  }
  return out;
}

}  // namespace

int run_in_tree(const std::string& module, InTreeCall& call) {
  const kernel::PluginLoader loader({frontends_dir()});
  Module m;
  try {
    m = load(loader, module, {});
  } catch (const sdk::Error& e) {
    throw sdk::Error("frontend_missing", "cannot load the front-end module '" + module + "' from " +
                                             frontends_dir() + ": " + e.what() +
                                             " (it is installed with flipper)");
  }
  ModuleHost host(call.command, call.opts, &call);
  return m.frontend->run(host);
}

int run_serve(const CommonOptions& opts) {
  InTreeCall call;
  call.command = "serve";
  call.opts = &opts;
  return run_in_tree("serve", call);
}

int run_accounts(const CommonOptions& opts, const AccountsArgs& args) {
  InTreeCall call;
  call.command = "accounts";
  call.opts = &opts;
  call.accounts = &args;
  return run_in_tree("serve", call);
}

int run_dds_node(const CommonOptions& opts) {
  InTreeCall call;
  call.command = "dds";
  call.opts = &opts;
  return run_in_tree("dds", call);
}

int run_dds_security(const std::string& action, const DdsSecurityArgs& args) {
  InTreeCall call;
  call.command = "dds security";
  call.security = &args;
  call.action = action;
  return run_in_tree("dds", call);
}

DdsServices DdsServices::start(wiring::SessionHost& host) {
  DdsServices services;
  if (!wants_dds_services(host.runtime->config)) return services;
  InTreeCall call;
  call.command = "dds services";
  call.host = &host;
  call.services = &services;
  run_in_tree("dds", call);
  return services;
}

// flipper frontend NAME [--config F] [--set k=v] [--param k=v]...: runs the front end NAME
// found in <exe>/../lib/flipper/frontends, then along the plugin path (plugin_paths,
// $FLIPPER_PLUGIN_PATH), with its parameters checked against its schema.
void add_frontend_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "frontend", "Run a front-end module (a plugin of kind frontend) on the session protocol");
  static CommonOptions opts;
  static std::string name;
  static std::vector<std::string> params;
  add_common_options(*cmd, opts);
  cmd->add_option(
         "name", name,
         "The front end's name: lib/flipper/frontends beside flipper, then the plugin path")
      ->required();
  cmd->add_option("--param", params,
                  "A parameter of the front end: --param key=value (repeatable)");
  on_run(*cmd, [] {
    const kernel::Config config = load_config(opts);
    std::vector<std::string> path{frontends_dir()};
    for (auto& dir : kernel::PluginLoader::search_path_for(config)) path.push_back(dir);
    const kernel::PluginLoader loader(path);
    const auto schema = loader.open(name, sdk::PluginKind::frontend).schema();
    Module m = load(loader, name, parse_params(schema, params, "frontend." + name));
    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    ModuleHost host("frontend " + name, &opts, nullptr);
    return m.frontend->run(host);
  });
}

}  // namespace flipper::cli

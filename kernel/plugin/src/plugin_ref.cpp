// PluginRef's out-of-line parts: the message shape of a failed call and the call observer.
#include "flipper/kernel/plugin_ref.hpp"

#include <exception>

#include "flipper/sdk/errors.hpp"

namespace flipper::kernel {

std::string PluginId::label() const {
  return "plugin '" + name + "' (" + (file.empty() ? kind : file) + ")";
}

void throw_plugin_failure(const PluginId& plugin, std::string_view op, std::string_view message) {
  throw sdk::Error(sdk::codes::kPluginError,
                   plugin.label() + ": " + std::string(op) + ": " + std::string(message));
}

namespace detail {

std::atomic<PluginCallObserver> g_plugin_call_observer{nullptr};

void rethrow_plugin_failure(const PluginId& plugin, std::string_view op) {
  try {
    throw;
  } catch (const sdk::Error&) {
    throw;
  } catch (const std::exception& e) {
    throw_plugin_failure(plugin, op, e.what());
  } catch (...) {
    throw_plugin_failure(plugin, op, "unknown exception");
  }
}

}  // namespace detail

PluginCallObserver set_plugin_call_observer(PluginCallObserver observer) {
  return detail::g_plugin_call_observer.exchange(observer);
}

}  // namespace flipper::kernel

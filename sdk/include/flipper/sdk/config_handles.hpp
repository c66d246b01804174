#pragma once
/// @file config_handles.hpp
/// Typed handles of parameters and config keys, the one handle system of Flipper (docs/config.md
/// "Who declares a key"): a parameter's name, default, range (or choices) and description are
/// written once, in one constant, and both the schema and the reading come from it. A plugin
/// declares its params with them; the kernel and every layer above it declare their config keys
/// with them (dotted names, e.g. `session.k`), each layer its own schema fragment:
/// @code
///   namespace param = flipper::sdk::param;
///   enum class Shape { box, sphere };  // in the order of the names below
///   inline constexpr param::Double kSize{"size", 0.5, 1e-3, 1e3, "edge of the body, metres"};
///   inline constexpr param::Choice<Shape, 2> kShape{"shape", Shape::box, {"box", "sphere"},
///                                                   "body shape"};
///   static sdk::ParamSchema schema() { return param::schema(kSize, kShape); }
///   explicit MyWorld(const sdk::Params& p) : size_(param::get(p, kSize)),
///                                            shape_(param::get(p, kShape)) {}
/// @endcode
/// The kernel validates a config against the schema before it constructs the plugin, so `get`
/// reads values that are present, typed and in range; for a parameter a hand-made Params lacks
/// (tests), `get` answers the handle's default. Header-only: no exported symbol, no ABI.

#include <array>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/params.hpp"

namespace flipper::sdk::param {

/// A number read as `T` (int, std::size_t, double, ...); `min`/`max` inclusive, empty: unbounded
/// (for an integer, then the limits of `T`). Declared as `param::Int<T>` or `param::Double`.
template <class T>
struct Number {
  std::string_view name;
  T def;
  std::optional<T> min;
  std::optional<T> max;
  std::string_view doc;
};
template <class T = std::int64_t>
using Int = Number<T>;
using Double = Number<double>;

struct Bool {
  std::string_view name;
  bool def;
  std::string_view doc;
};

/// A string with any value.
struct Text {
  std::string_view name;
  std::string_view def;
  std::string_view doc;
};

/// One of N names, read as the enumerator `E` whose value is the name's position: the
/// enumerators of `E` are 0 .. N-1 in the order of `names`.
template <class E, std::size_t N>
struct Choice {
  std::string_view name;
  E def;
  std::array<std::string_view, N> names;
  std::string_view doc;
};

/// A filesystem path, resolved against the config file's directory by the kernel. `required`:
/// no default, the config must give it (then `def` is unused).
struct Path {
  std::string_view name;
  std::string_view def;
  std::string_view doc;
  bool required = false;
};

/// A list of strings; `def` holds the default's elements.
template <std::size_t N>
struct TextList {
  std::string_view name;
  std::array<std::string_view, N> def;
  std::string_view doc;
};

/// A list of paths, each resolved like a Path; `def` holds the default's elements.
template <std::size_t N>
struct PathList {
  std::string_view name;
  std::array<std::string_view, N> def;
  std::string_view doc;
};

/// A list of numbers; `def` holds the default's elements.
template <std::size_t N>
struct DoubleList {
  std::string_view name;
  std::array<double, N> def;
  std::string_view doc;
};

/// A subset of N names, read as one flag per name (in the order of `names`); default: all of
/// them. An element that is none of the names is Error(bad_config) naming it.
template <std::size_t N>
struct Subset {
  std::string_view name;
  std::array<std::string_view, N> names;
  std::string_view doc;
};

namespace detail {
inline std::string str(std::string_view s) {
  return std::string(s);
}
template <class T>
std::optional<double> bound(const std::optional<T>& b) {
  if (!b) return std::nullopt;
  return static_cast<double>(*b);
}
template <std::size_t N>
std::string join(const std::array<std::string_view, N>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + str(n);
  return out;
}
[[noreturn]] inline void refuse(std::string_view name, const std::string& what) {
  throw sdk::Error(sdk::codes::kBadConfig, "param '" + str(name) + "' " + what);
}
}  // namespace detail

template <class T>
void add(sdk::ParamSchema& s, const Number<T>& p) {
  if constexpr (std::is_floating_point_v<T>)
    s.add_double(detail::str(p.name), p.def, detail::str(p.doc), detail::bound(p.min),
                 detail::bound(p.max));
  else
    s.add_int(detail::str(p.name), static_cast<std::int64_t>(p.def), detail::str(p.doc),
              detail::bound(p.min), detail::bound(p.max));
}
inline void add(sdk::ParamSchema& s, const Bool& p) {
  s.add_bool(detail::str(p.name), p.def, detail::str(p.doc));
}
inline void add(sdk::ParamSchema& s, const Text& p) {
  s.add_string(detail::str(p.name), detail::str(p.def), detail::str(p.doc));
}
template <class E, std::size_t N>
void add(sdk::ParamSchema& s, const Choice<E, N>& p) {
  std::vector<std::string> names(p.names.begin(), p.names.end());
  s.add_string(detail::str(p.name), detail::str(p.names.at(static_cast<std::size_t>(p.def))),
               detail::str(p.doc), std::move(names));
}
inline void add(sdk::ParamSchema& s, const Path& p) {
  std::optional<std::string> def;
  if (!p.required) def = detail::str(p.def);
  s.add_path(detail::str(p.name), def, detail::str(p.doc), p.required);
}
template <std::size_t N>
void add(sdk::ParamSchema& s, const TextList<N>& p) {
  s.add_string_list(detail::str(p.name), std::vector<std::string>(p.def.begin(), p.def.end()),
                    detail::str(p.doc));
}

template <std::size_t N>
void add(sdk::ParamSchema& s, const PathList<N>& p) {
  s.add_path_list(detail::str(p.name), std::vector<std::string>(p.def.begin(), p.def.end()),
                  detail::str(p.doc));
}
template <std::size_t N>
void add(sdk::ParamSchema& s, const DoubleList<N>& p) {
  s.add_double_list(detail::str(p.name), std::vector<double>(p.def.begin(), p.def.end()),
                    detail::str(p.doc));
}

template <std::size_t N>
void add(sdk::ParamSchema& s, const Subset<N>& p) {
  s.add_string_list(detail::str(p.name), std::vector<std::string>(p.names.begin(), p.names.end()),
                    detail::str(p.doc));
}

/// The schema of the given handles, in their order.
template <class... Handles>
sdk::ParamSchema schema(const Handles&... handles) {
  sdk::ParamSchema s;
  (add(s, handles), ...);
  return s;
}

/// One schema of several fragments, in their order (sections and keys alike): how a host
/// composes the kernel's keys with those each layer above it declares (docs/config.md). A key or
/// section two fragments both declare is a programming error (std::logic_error naming it): each
/// key has one owner.
inline sdk::ParamSchema compose(std::initializer_list<const sdk::ParamSchema*> fragments) {
  sdk::ParamSchema out;
  for (const sdk::ParamSchema* f : fragments) {
    for (const auto& section : f->sections) {
      if (out.find_section(section.name) != nullptr)
        throw std::logic_error("config section '" + section.name + "' is declared twice");
      out.sections.push_back(section);
    }
    for (const auto& spec : f->params) {
      if (out.find(spec.name) != nullptr)
        throw std::logic_error("config key '" + spec.name + "' is declared twice");
      out.params.push_back(spec);
    }
  }
  return out;
}

/// The value as `T`. A value outside the handle's [min, max] or `T`'s range is Error(bad_config)
/// naming the param: the kernel validates before it constructs a plugin, but a host that does not
/// (a test, another program) must not get a value the schema refuses.
template <class T>
T get(const sdk::Params& params, const Number<T>& p) {
  const std::string name(p.name);
  if (!params.has(name)) return p.def;
  const double x = std::is_floating_point_v<T> ? params.get_double(name)
                                               : static_cast<double>(params.get_int(name));
  if ((p.min && x < static_cast<double>(*p.min)) || (p.max && x > static_cast<double>(*p.max))) {
    auto text = [](auto v) {
      std::ostringstream out;
      out << v;
      return out.str();
    };
    auto bound = [&](const std::optional<T>& b, const char* none) {
      return b ? text(*b) : std::string(none);
    };
    const std::string value =
        std::is_floating_point_v<T> ? text(x) : std::to_string(params.get_int(name));
    detail::refuse(p.name, "= " + value + " is out of range [" + bound(p.min, "-inf") + ", " +
                               bound(p.max, "inf") + "]");
  }
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(params.get_double(name));
  } else {
    const std::int64_t v = params.get_int(name);
    bool fits = false;
    if constexpr (std::numeric_limits<T>::is_signed)
      fits = v >= static_cast<std::int64_t>(std::numeric_limits<T>::min()) &&
             v <= static_cast<std::int64_t>(std::numeric_limits<T>::max());
    else
      fits = v >= 0 && static_cast<std::uint64_t>(v) <=
                           static_cast<std::uint64_t>(std::numeric_limits<T>::max());
    if (!fits) detail::refuse(p.name, "= " + std::to_string(v) + " does not fit its type");
    return static_cast<T>(v);
  }
}
inline bool get(const sdk::Params& params, const Bool& p) {
  const std::string name(p.name);
  return params.has(name) ? params.get_bool(name) : p.def;
}
inline std::string get(const sdk::Params& params, const Text& p) {
  const std::string name(p.name);
  return params.has(name) ? params.get_string(name) : detail::str(p.def);
}
/// The path (resolved by the kernel); a required path a hand-made Params lacks is
/// Error(bad_config).
inline std::string get(const sdk::Params& params, const Path& p) {
  const std::string name(p.name);
  if (params.has(name)) return params.get_string(name);
  if (p.required) detail::refuse(p.name, "is required");
  return detail::str(p.def);
}
template <class E, std::size_t N>
E get(const sdk::Params& params, const Choice<E, N>& p) {
  const std::string name(p.name);
  if (!params.has(name)) return p.def;
  const std::string& value = params.get_string(name);
  for (std::size_t i = 0; i < N; ++i)
    if (p.names[i] == value) return static_cast<E>(i);
  detail::refuse(p.name, "= \"" + value + "\" is not one of " + detail::join(p.names));
}
template <std::size_t N>
std::vector<std::string> get(const sdk::Params& params, const TextList<N>& p) {
  const std::string name(p.name);
  if (params.has(name)) return params.get_string_list(name);
  return std::vector<std::string>(p.def.begin(), p.def.end());
}

template <std::size_t N>
std::vector<std::string> get(const sdk::Params& params, const PathList<N>& p) {
  const std::string name(p.name);
  if (params.has(name)) return params.get_string_list(name);
  return std::vector<std::string>(p.def.begin(), p.def.end());
}
template <std::size_t N>
std::vector<double> get(const sdk::Params& params, const DoubleList<N>& p) {
  const std::string name(p.name);
  if (params.has(name)) return params.get_double_list(name);
  return std::vector<double>(p.def.begin(), p.def.end());
}

template <std::size_t N>
std::array<bool, N> get(const sdk::Params& params, const Subset<N>& p) {
  std::array<bool, N> chosen{};
  const std::string name(p.name);
  if (!params.has(name)) {
    chosen.fill(true);
    return chosen;
  }
  for (const std::string& element : params.get_string_list(name)) {
    std::size_t i = 0;
    while (i < N && p.names[i] != element) ++i;
    if (i == N)
      detail::refuse(p.name, "has '" + element + "', which is not one of " + detail::join(p.names));
    chosen[i] = true;
  }
  return chosen;
}

/// The name a Choice value stands for.
template <class E, std::size_t N>
std::string_view name_of(const Choice<E, N>& p, E value) {
  return p.names.at(static_cast<std::size_t>(value));
}

}  // namespace flipper::sdk::param

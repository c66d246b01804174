#pragma once
// The wire form of /sempre requests as the 2018 web client builds them (docs/sempre.md): GET
// /sempre?format=lisp2json&q=<command>&sessionId=<id>, the values encoded like JavaScript's
// encodeURIComponent, the world sent before every query as (:context "<JSON text>"). Shared by
// the /sempre tests and its benchmark.
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace flipper::sempretest {

using nlohmann::json;

/// JavaScript's encodeURIComponent: everything but A-Z a-z 0-9 - _ . ! ~ * ' ( ) as %XX of the
/// UTF-8 bytes (a space is %20, never '+').
inline std::string encode_uri_component(const std::string& s) {
  static const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (const unsigned char c : s) {
    if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
        std::string_view("-_.!~*'()").find(static_cast<char>(c)) != std::string_view::npos) {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

/// The request target the client builds for one command.
inline std::string sempre_target(const std::string& command, const std::string& session) {
  return "/sempre?format=lisp2json&q=" + encode_uri_component(command) +
         "&sessionId=" + encode_uri_component(session);
}

/// A world object of the protocol (configs/worlds/*.json, worlds.jsonl records) as the client's
/// context: {"robot": [x, y, carried], "world": [walls..., items...], "rooms": {...}}, keys in
/// that order.
inline std::string context_text(const json& world) {
  json carried = json::array();
  if (world["robot"].contains("holding"))
    for (const auto& h : world["robot"]["holding"]) carried.push_back({h["color"], h["shape"]});
  std::string cells;
  for (const auto& w : world["walls"])
    cells +=
        (cells.empty() ? "" : ",") + json::array({w[0], w[1], "wall", nullptr, nullptr}).dump();
  for (const auto& i : world["items"])
    cells += (cells.empty() ? "" : ",") +
             json::array({i["x"], i["y"], "item", i["color"], i["shape"]}).dump();
  return "{\"robot\":" + json::array({world["robot"]["x"], world["robot"]["y"], carried}).dump() +
         ",\"world\":[" + cells + "],\"rooms\":" + world["rooms"].dump() + "}";
}

/// (:context "<the world's JSON text>")
inline std::string context_command(const json& world) {
  return "(:context " + json(context_text(world)).dump() + ")";
}

/// (:q "<text>")
inline std::string query_command(const std::string& text) {
  return "(:q " + json(text).dump() + ")";
}

}  // namespace flipper::sempretest

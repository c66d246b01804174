#pragma once
// A /sempre client for the tests (docs/sempre.md): the requests of sempre_wire.hpp sent with
// httplib, the answers parsed.
#include <httplib.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "sempre_wire.hpp"

namespace flipper::sempretest {

using nlohmann::json;

struct SempreReply {
  int status = 0;
  json body;
  std::string allow_origin;
  std::string content_type;
};

inline SempreReply sempre_get_target(httplib::Client& c, const std::string& target) {
  c.set_url_encode(false);  // the target is sent as the browser sends it ('+' stays '+')
  auto res = c.Get(target.c_str());
  REQUIRE(res);
  SempreReply r;
  r.status = res->status;
  r.body = json::parse(res->body, nullptr, false);
  r.allow_origin = res->get_header_value("Access-Control-Allow-Origin");
  r.content_type = res->get_header_value("Content-Type");
  return r;
}

inline SempreReply sempre_get(httplib::Client& c, const std::string& command,
                              const std::string& session) {
  return sempre_get_target(c, sempre_target(command, session));
}

/// The 2018 study map (configs/worlds/study2018.json).
inline json study_map() {
  std::ifstream in(std::string(FLIPPER_SOURCE_DIR) + "/configs/worlds/study2018.json");
  REQUIRE(in.good());
  std::stringstream s;
  s << in.rdbuf();
  return json::parse(s.str());
}

}  // namespace flipper::sempretest

// The keys and defaults of nav2_map_server's loadMapYaml: image, resolution, origin [x, y, yaw],
// free_thresh, occupied_thresh and negate are required, mode defaults to trinary; a relative
// image path is relative to the YAML file's folder.
#include "map_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>

#include "flipper/sdk/errors.hpp"

namespace flipper::plugins::ros_map {

namespace sdk = flipper::sdk;

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw sdk::Error(sdk::codes::kBadWorld, path + ": " + what);
}

YAML::Node require(const YAML::Node& doc, const char* key, const std::string& path) {
  const YAML::Node n = doc[key];
  if (!n) fail(path, std::string("missing key '") + key + "'");
  return n;
}

template <class T>
T scalar(const YAML::Node& n, const std::string& key, const char* type, const std::string& path) {
  if (!n.IsScalar()) fail(path, "'" + key + "' must be " + type);
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    fail(path, "'" + key + "' must be " + type + ", got '" + n.Scalar() + "'");
  }
}

bool negate_of(const YAML::Node& n, const std::string& path) {
  // Nav2 reads an int (any non-zero value negates); true/false are accepted as well.
  if (!n.IsScalar()) fail(path, "'negate' must be 0 or 1");
  const std::string& s = n.Scalar();
  if (s == "true" || s == "True") return true;
  if (s == "false" || s == "False") return false;
  return scalar<long long>(n, "negate", "0 or 1", path) != 0;
}

}  // namespace

const char* mode_name(MapMode mode) {
  switch (mode) {
    case MapMode::trinary:
      return "trinary";
    case MapMode::scale:
      return "scale";
    case MapMode::raw:
      return "raw";
  }
  return "trinary";
}

MapYaml parse_map_yaml(const std::string& text, const std::string& path) {
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    fail(path, std::string("not valid YAML: ") + e.what());
  }
  if (!doc.IsMap())
    fail(path, "a map_server YAML must be a mapping (image, resolution, origin...)");
  MapYaml m;
  const std::string image =
      scalar<std::string>(require(doc, "image", path), "image", "a file name", path);
  if (image.empty()) fail(path, "'image' is empty");
  std::filesystem::path image_path(image);
  if (image_path.is_relative()) image_path = std::filesystem::path(path).parent_path() / image_path;
  m.image = image_path.string();

  m.resolution = scalar<double>(require(doc, "resolution", path), "resolution", "a number", path);
  if (!(m.resolution > 0) || !std::isfinite(m.resolution))
    fail(path, "'resolution' must be a positive number of metres per cell");

  const YAML::Node origin = require(doc, "origin", path);
  if (!origin.IsSequence() || origin.size() != 3)
    fail(path, "'origin' must be [x, y, yaw] (metres, metres, radians)");
  m.origin_x = scalar<double>(origin[0], "origin[0]", "a number", path);
  m.origin_y = scalar<double>(origin[1], "origin[1]", "a number", path);
  const double yaw = scalar<double>(origin[2], "origin[2]", "a number", path);
  if (!std::isfinite(m.origin_x) || !std::isfinite(m.origin_y))
    fail(path, "'origin' must be finite");
  if (yaw != 0)
    fail(path, "'origin' yaw is " + origin[2].Scalar() +
                   "; only maps with yaw 0 are supported (rotate the image instead)");

  m.negate = negate_of(require(doc, "negate", path), path);
  m.occupied_thresh =
      scalar<double>(require(doc, "occupied_thresh", path), "occupied_thresh", "a number", path);
  m.free_thresh =
      scalar<double>(require(doc, "free_thresh", path), "free_thresh", "a number", path);
  if (!(m.occupied_thresh >= 0 && m.occupied_thresh <= 1))
    fail(path, "'occupied_thresh' must lie in [0, 1]");
  if (!(m.free_thresh >= 0 && m.free_thresh <= 1)) fail(path, "'free_thresh' must lie in [0, 1]");
  if (m.free_thresh > m.occupied_thresh)
    fail(path, "'free_thresh' (" + std::to_string(m.free_thresh) +
                   ") must not exceed 'occupied_thresh' (" + std::to_string(m.occupied_thresh) +
                   ")");

  if (const YAML::Node mode = doc["mode"]) {
    const std::string s = scalar<std::string>(mode, "mode", "trinary, scale or raw", path);
    if (s == "trinary")
      m.mode = MapMode::trinary;
    else if (s == "scale")
      m.mode = MapMode::scale;
    else if (s == "raw")
      m.mode = MapMode::raw;
    else
      fail(path, "'mode' is '" + s + "'; expected trinary, scale or raw");
  }
  if (m.mode == MapMode::scale && !(m.free_thresh < m.occupied_thresh))
    fail(path, "mode scale needs free_thresh < occupied_thresh");
  return m;
}

}  // namespace flipper::plugins::ros_map

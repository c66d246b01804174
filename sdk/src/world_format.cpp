#include "flipper/sdk/world_format.hpp"

#include <algorithm>
#include <charconv>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

#include "flipper/sdk/errors.hpp"
#include "point_scan.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {
namespace world_format {
namespace {

using json = nlohmann::json;

[[noreturn]] void fail(const std::string& message) {
  throw Error(codes::kBadWorld, message);
}

// nlohmann keeps only the last of duplicate keys, silently. A SAX pass sees every key, so a stack
// of key sets (one per open object) finds duplicates and names where they are. (A parser callback
// did the same, but nlohmann's callback parser rescans an array's elements at the end of every
// object in it: 30,000 items took seconds.)
class DuplicateKeyCheck : public nlohmann::json_sax<json> {
 public:
  // The world's tree is built in the same pass (one lexing of a large wall list, not two). With
  // `fast_walls`, a top-level "walls" list of plain integer points is collected as cells without
  // a tree (its tree is an empty array); anything else in it sets walls_failed() and the caller
  // parses again without the shortcut, for the exact error message.
  DuplicateKeyCheck(json& root, int dims, bool fast_walls)
      : dom_(root, true), dims_(dims), fast_walls_(fast_walls) {}
  bool walls_failed() const { return walls_bad_; }
  bool walls_collected() const { return walls_done_; }
  std::vector<Cell>& walls() { return walls_; }

  bool null() override { return wdepth_ ? bad() : value() && dom_.null(); }
  bool boolean(bool v) override { return wdepth_ ? bad() : value() && dom_.boolean(v); }
  bool number_integer(number_integer_t v) override {
    return wdepth_ ? coordinate(v) : value() && dom_.number_integer(v);
  }
  bool number_unsigned(number_unsigned_t v) override {
    if (wdepth_)
      return v > static_cast<number_unsigned_t>(detail::kMaxCoordinate)
                 ? bad()
                 : coordinate(static_cast<std::int64_t>(v));
    return value() && dom_.number_unsigned(v);
  }
  bool number_float(number_float_t v, const string_t& s) override {
    return wdepth_ ? bad() : value() && dom_.number_float(v, s);
  }
  bool string(string_t& v) override { return wdepth_ ? bad() : value() && dom_.string(v); }
  bool binary(binary_t& v) override { return wdepth_ ? bad() : value() && dom_.binary(v); }
  bool start_object(std::size_t n) override {
    if (wdepth_) {
      ++wdepth_;
      return bad();
    }
    frames_.push_back({false, {}, {}, 0});
    return dom_.start_object(n);
  }
  bool start_array(std::size_t n) override {
    if (wdepth_) {
      if (++wdepth_ == 2)
        coords_ = 0;
      else
        bad();
      return true;
    }
    if (fast_walls_ && walls_key_ && frames_.size() == 1) {
      wdepth_ = 1;
      return true;
    }
    frames_.push_back({true, {}, {}, 0});
    return dom_.start_array(n);
  }
  bool key(string_t& key) override {
    if (wdepth_) return true;  // inside a malformed wall list: the slow pass reports it
    Frame& f = frames_.back();
    if (!f.keys.insert(key).second) {
      const std::string path = path_of(frames_.size() - 1);
      if (path == "rooms") fail("rooms: duplicate room name \"" + key + "\"");
      if (path.empty()) fail("duplicate key \"" + key + "\"");
      fail(path + ": duplicate key \"" + key + "\"");
    }
    f.last_key = key;
    if (frames_.size() == 1) walls_key_ = key == "walls";
    return dom_.key(key);
  }
  bool end_object() override {
    if (wdepth_) {
      --wdepth_;
      return true;
    }
    return end() && dom_.end_object();
  }
  bool end_array() override {
    if (wdepth_) {
      if (wdepth_ == 2 && !walls_bad_) {
        if (coords_ != dims_)
          bad();
        else
          walls_.push_back({xyz_[0], xyz_[1], xyz_[2]});
      }
      if (--wdepth_ == 0) {  // the wall list ends: its tree is an empty array
        walls_done_ = !walls_bad_;
        return value() && dom_.start_array(0) && dom_.end_array();
      }
      return true;
    }
    return end() && dom_.end_array();
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    fail(std::string("world is not valid JSON: ") + e.what());
  }

 private:
  struct Frame {
    bool is_array;
    std::set<std::string> keys;
    std::string last_key;
    std::size_t index;
  };
  bool value() {
    if (!frames_.empty() && frames_.back().is_array) ++frames_.back().index;
    return true;
  }
  bool end() {
    frames_.pop_back();
    return value();
  }
  // "rooms", "items[3]", "robot.holding[0]": where frame k sits (built only for a message).
  std::string path_of(std::size_t k) const {
    std::string path;
    for (std::size_t i = 0; i < k; ++i) {
      const Frame& f = frames_[i];
      if (f.is_array)
        path += "[" + std::to_string(f.index) + "]";
      else
        path += (path.empty() ? "" : ".") + f.last_key;
    }
    return path;
  }
  bool bad() {
    walls_bad_ = true;
    return true;
  }
  bool coordinate(std::int64_t v) {
    constexpr std::int64_t kLimit = detail::kMaxCoordinate;  // as coordinate() below
    if (wdepth_ != 2 || coords_ >= dims_ || v < -kLimit || v > kLimit) return bad();
    xyz_[coords_++] = static_cast<std::int32_t>(v);
    return true;
  }
  std::vector<Frame> frames_;
  nlohmann::detail::json_sax_dom_parser<json> dom_;
  int dims_;
  bool fast_walls_;
  bool walls_key_ = false;  // the last top-level key was "walls"
  int wdepth_ = 0;          // nesting inside the wall list being collected (0: not in it)
  int coords_ = 0;          // coordinates of the point being read
  std::int32_t xyz_[3] = {0, 0, 0};
  bool walls_bad_ = false, walls_done_ = false;
  std::vector<Cell> walls_;
};

std::string type_name(const json& v) {
  if (v.is_number_float()) return "a fractional number";
  if (v.is_number()) return "an integer";
  if (v.is_string()) return "a string";
  if (v.is_boolean()) return "a boolean";
  if (v.is_null()) return "null";
  if (v.is_array()) return "an array";
  return "an object";
}

std::int32_t coordinate(const json& v, const std::string& what) {
  if (!v.is_number_integer()) fail(what + " must be an integer, not " + type_name(v));
  const auto i = v.get<std::int64_t>();
  constexpr std::int64_t kLimit = detail::kMaxCoordinate;
  if (i < -kLimit || i > kLimit) fail(what + " is out of range (" + std::to_string(i) + ")");
  return static_cast<std::int32_t>(i);
}

Cell point(const json& v, int dims, const std::string& where) {
  if (!v.is_array() || v.size() != static_cast<std::size_t>(dims))
    fail(where + ": a point must be an array of " + std::to_string(dims) + " integers");
  Cell c;
  c.x = coordinate(v[0], where + ": x");
  c.y = coordinate(v[1], where + ": y");
  if (dims == 3) c.z = coordinate(v[2], where + ": z");
  return c;
}

// A well-formed point without building the names used in messages (a wall list has thousands).
bool plain_point(const json& v, int dims, Cell& c) {
  constexpr std::int64_t kLimit = detail::kMaxCoordinate;
  if (!v.is_array() || v.size() != static_cast<std::size_t>(dims)) return false;
  std::int32_t xyz[3] = {0, 0, 0};
  for (int a = 0; a < dims; ++a) {
    const json& e = v[static_cast<std::size_t>(a)];
    if (!e.is_number_integer()) return false;
    const auto i = e.get<std::int64_t>();
    if (i < -kLimit || i > kLimit) return false;
    xyz[a] = static_cast<std::int32_t>(i);
  }
  c = {xyz[0], xyz[1], xyz[2]};
  return true;
}

std::vector<Cell> point_list(const json& v, int dims, const std::string& where) {
  if (!v.is_array()) fail(where + " must be an array of points, not " + type_name(v));
  std::vector<Cell> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    Cell c;
    if (plain_point(v[i], dims, c))
      out.push_back(c);
    else
      out.push_back(point(v[i], dims, where + "[" + std::to_string(i) + "]"));  // says why
  }
  return out;
}

Cell position(const json& obj, int dims, const std::string& where) {
  static const char* const kAxes[] = {"x", "y", "z"};
  std::int32_t xyz[3] = {0, 0, 0};
  for (int a = 0; a < dims; ++a) {
    auto it = obj.find(kAxes[a]);
    if (it == obj.end()) fail(where + ": missing \"" + kAxes[a] + "\"");
    xyz[a] = coordinate(*it, where + ": " + kAxes[a]);
  }
  return {xyz[0], xyz[1], xyz[2]};
}

std::string word(const json& obj, const char* key, const std::string& where) {
  auto it = obj.find(key);
  if (it == obj.end()) fail(where + ": missing \"" + key + "\"");
  if (!it->is_string()) fail(where + ": " + key + " must be a string, not " + type_name(*it));
  const auto& s = it->get_ref<const std::string&>();
  if (s.empty()) fail(where + ": " + key + " must not be empty");
  return s;
}

// An item object: colour, shape, optional id (checked for type here, uniqueness by the caller).
ItemInfo item_info(const json& v, const std::string& where, std::optional<std::int64_t>& id) {
  if (!v.is_object()) fail(where + " must be an object, not " + type_name(v));
  ItemInfo info;
  info.color = word(v, "color", where);
  info.shape = word(v, "shape", where);
  id.reset();
  if (auto it = v.find("id"); it != v.end()) {
    if (!it->is_number_integer()) fail(where + ": id must be an integer, not " + type_name(*it));
    id = it->get<std::int64_t>();
    if (*id < 0) fail(where + ": id must not be negative");
  }
  return info;
}

const json* member(const json& obj, const char* key) {
  auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

void grow(Bounds& b, const Cell& c) {
  b.min = {std::min(b.min.x, c.x), std::min(b.min.y, c.y), std::min(b.min.z, c.z)};
  b.max = {std::max(b.max.x, c.x), std::max(b.max.y, c.y), std::max(b.max.z, c.z)};
}

std::string placement_problem(const Cell& c, const Geometry& g) {
  if (!g.in_bounds(c)) return "is outside the bounds";
  if (!g.is_free(c)) return "is on a wall";
  return {};
}

}  // namespace

std::string describe(const Cell& c, int dims) {
  std::string s = "(" + std::to_string(c.x) + "," + std::to_string(c.y);
  if (dims == 3) s += "," + std::to_string(c.z);
  return s + ")";
}

namespace {
WorldDocument parse_world_in(std::string_view text, int dims);
}  // namespace

WorldDocument parse_world(std::string_view text, int dims) {
  if (dims != 2 && dims != 3) throw Error(codes::kInternal, "parse_world: dims must be 2 or 3");
  try {
    return parse_world_in(text, dims);
  } catch (const Error& e) {
    // Only on the error path: does the text read as a world of the other dimensions?
    const int other = 5 - dims;
    try {
      (void)parse_world_in(text, other);
    } catch (const Error&) {
      throw e;
    }
    throw OtherDimsError(other, e.what());
  }
}

std::uint64_t cell_count(const Bounds& box) {
  auto extent = [](std::int64_t lo, std::int64_t hi) {
    return hi < lo ? std::uint64_t{0} : static_cast<std::uint64_t>(hi - lo) + 1;
  };
  return extent(box.min.x, box.max.x) * extent(box.min.y, box.max.y) * extent(box.min.z, box.max.z);
}

void check_cells(std::uint64_t cells, const WorldLimits& limits) {
  if (cells > limits.max_cells)
    throw Error(codes::kWorldTooLarge,
                "the world has " + std::to_string(cells) +
                    " cells; the limit is world.max_cells = " + std::to_string(limits.max_cells));
}

namespace {

// The document of `text`; `split`: the point lists already read from the text, whose values
// there were replaced by [] and {} (parse_world_in).
WorldDocument parse_tree(std::string_view text, int dims, detail::PointLists* split) {
  std::vector<Cell>* split_walls = split != nullptr && split->walls ? &*split->walls : nullptr;
  json root;
  std::vector<Cell> fast_walls;
  bool have_fast_walls = false;
  try {
    DuplicateKeyCheck check(root, dims, true);
    json::sax_parse(text.begin(), text.end(), &check);
    if (check.walls_failed()) {
      root = json();
      DuplicateKeyCheck slow(root, dims, false);
      json::sax_parse(text.begin(), text.end(), &slow);
    } else if (check.walls_collected()) {
      fast_walls = std::move(check.walls());
      have_fast_walls = true;
    }
  } catch (const json::exception& e) {  // syntax, and numbers beyond double range (1e999)
    fail(std::string("world is not valid JSON: ") + e.what());
  }
  if (!root.is_object()) fail("world must be a JSON object, not " + type_name(root));

  WorldDocument doc;
  doc.dims = dims;
  static const std::set<std::string> kKnown = {"walls", "octomap", "items",
                                               "robot", "rooms",   "bounds"};
  for (auto it = root.begin(); it != root.end(); ++it)
    if (!kKnown.count(it.key())) doc.extra.emplace(it.key(), it.value().dump());

  if (const json* walls = member(root, "walls")) {
    doc.has_walls = true;
    doc.walls = split_walls != nullptr ? std::move(*split_walls)
                : have_fast_walls      ? std::move(fast_walls)
                                       : point_list(*walls, dims, "walls");
  }
  if (const json* octo = member(root, "octomap")) {
    if (!octo->is_string()) fail("octomap must be a file name (string), not " + type_name(*octo));
    doc.octomap = octo->get<std::string>();
  }

  // Items and held items, with the ids they carry; missing ids are filled in afterwards.
  std::vector<std::optional<std::int64_t>> lying_ids, held_ids;
  std::set<std::int64_t> used;
  auto note_id = [&used](const std::optional<std::int64_t>& id, const std::string& where) {
    if (id && !used.insert(*id).second) fail(where + ": duplicate id " + std::to_string(*id));
  };
  if (const json* items = member(root, "items")) {
    if (!items->is_array()) fail("items must be an array, not " + type_name(*items));
    for (std::size_t i = 0; i < items->size(); ++i) {
      const std::string where = "items[" + std::to_string(i) + "]";
      std::optional<std::int64_t> id;
      LyingItem li;
      li.item = item_info((*items)[i], where, id);
      li.at = position((*items)[i], dims, where);
      note_id(id, where);
      lying_ids.push_back(id);
      doc.items.push_back(std::move(li));
    }
  }
  const json* robot = member(root, "robot");
  if (robot == nullptr) fail("robot: missing (a world needs a robot)");
  if (!robot->is_object()) fail("robot must be an object, not " + type_name(*robot));
  doc.robot = position(*robot, dims, "robot");
  if (const json* holding = member(*robot, "holding")) {
    if (!holding->is_array())
      fail("robot.holding must be an array of items, not " + type_name(*holding));
    for (std::size_t i = 0; i < holding->size(); ++i) {
      const std::string where = "robot.holding[" + std::to_string(i) + "]";
      std::optional<std::int64_t> id;
      doc.holding.push_back(item_info((*holding)[i], where, id));
      note_id(id, where);
      held_ids.push_back(id);
    }
  }
  std::int64_t next = 0;
  auto assign = [&](std::optional<std::int64_t>& id, ItemInfo& info) {
    if (!id) {
      while (used.count(next)) ++next;
      id = next++;
    }
    info.id = *id;
  };
  for (std::size_t i = 0; i < doc.items.size(); ++i) assign(lying_ids[i], doc.items[i].item);
  for (std::size_t i = 0; i < doc.holding.size(); ++i) assign(held_ids[i], doc.holding[i]);
  doc.next_item_id = 0;
  for (const auto& li : doc.items) doc.next_item_id = std::max(doc.next_item_id, li.item.id + 1);
  for (const auto& h : doc.holding) doc.next_item_id = std::max(doc.next_item_id, h.id + 1);

  auto add_room = [&doc](const std::string& name, std::vector<Cell> pts) {
    Area area = pts;
    areas::normalize(area);
    doc.rooms.emplace(name, std::move(area));
    doc.room_points.emplace_back(name, std::move(pts));
  };
  if (split != nullptr && split->rooms) {
    for (auto& [name, pts] : *split->rooms) add_room(name, std::move(pts));
  } else if (const json* rooms = member(root, "rooms")) {
    if (!rooms->is_object())
      fail("rooms must be an object mapping names to points, not " + type_name(*rooms));
    for (auto it = rooms->begin(); it != rooms->end(); ++it) {
      if (it.key().empty()) fail("rooms: a room name must not be empty");
      add_room(it.key(), point_list(it.value(), dims, "rooms." + it.key()));
    }
  }

  if (const json* bounds = member(root, "bounds")) {
    if (!bounds->is_object()) fail("bounds must be an object {\"min\": point, \"max\": point}");
    const json* lo = member(*bounds, "min");
    const json* hi = member(*bounds, "max");
    if (lo == nullptr || hi == nullptr) fail("bounds: needs both \"min\" and \"max\"");
    Bounds b{point(*lo, dims, "bounds.min"), point(*hi, dims, "bounds.max")};
    if (b.max.x < b.min.x || b.max.y < b.min.y || b.max.z < b.min.z)
      fail("bounds: min " + describe(b.min, dims) + " exceeds max " + describe(b.max, dims));
    doc.bounds = b;
  }
  areas::normalize(doc.walls);
  return doc;
}

// Plain wall and room lists are read from the text (detail::scan_point_lists) and the rest parsed
// with [] and {} in their place; when that fails, or neither is plain, the text as sent is parsed
// whole, which gives the exact error (its message's byte positions are the sent text's).
WorldDocument parse_world_in(std::string_view text, int dims) {
  if (auto split = detail::scan_point_lists(text, dims)) {
    std::vector<std::pair<detail::PointLists::Span, const char*>> cut;
    if (split->walls) cut.emplace_back(split->walls_at, "[]");
    if (split->rooms) cut.emplace_back(split->rooms_at, "{}");
    std::sort(cut.begin(), cut.end(),
              [](const auto& a, const auto& b) { return a.first.begin < b.first.begin; });
    std::string rest;
    rest.reserve(text.size());
    std::size_t at = 0;
    for (const auto& [span, empty] : cut) {
      rest.append(text.substr(at, span.begin - at)).append(empty);
      at = span.end;
    }
    rest.append(text.substr(at));
    try {
      return parse_tree(rest, dims, &*split);
    } catch (const Error&) {  // read again below, as sent
    }
  }
  return parse_tree(text, dims, nullptr);
}

}  // namespace

Bounds default_bounds(const WorldDocument& doc) {
  Bounds b{doc.robot, doc.robot};
  for (const Cell& c : doc.walls) grow(b, c);
  for (const auto& li : doc.items) grow(b, li.at);
  for (const auto& [name, area] : doc.rooms)
    for (const Cell& c : area) grow(b, c);
  return b;
}

Bounds effective_bounds(const WorldDocument& doc) {
  return doc.bounds ? *doc.bounds : default_bounds(doc);
}

void check_placement(const WorldDocument& doc, const Geometry& g) {
  const int dims = doc.dims;
  // Walls come sorted; report the first outside point by its value.
  for (const Cell& c : doc.walls)
    if (!g.in_bounds(c)) fail("walls: point " + describe(c, dims) + " is outside the bounds");
  for (const auto& [name, pts] : doc.room_points)
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (!g.in_bounds(pts[i]))
        fail("rooms." + name + "[" + std::to_string(i) + "] " + describe(pts[i], dims) +
             " is outside the bounds");
  if (auto p = placement_problem(doc.robot, g); !p.empty())
    fail("robot " + describe(doc.robot, dims) + " " + p);
  for (std::size_t i = 0; i < doc.items.size(); ++i) {
    const auto& li = doc.items[i];
    if (auto p = placement_problem(li.at, g); !p.empty())
      fail("items[" + std::to_string(i) + "] (id " + std::to_string(li.item.id) + ") at " +
           describe(li.at, dims) + " " + p);
  }
}

WorldState make_state(WorldDocument&& doc, std::shared_ptr<const Geometry> geometry) {
  WorldState s;
  s.geometry = std::move(geometry);
  s.rooms = std::make_shared<const RoomMap>(std::move(doc.rooms));
  s.robot = doc.robot;
  s.items = std::move(doc.items);
  s.held = std::move(doc.holding);
  s.next_item_id = doc.next_item_id;
  return s;
}

namespace {

// The writers below produce exactly what nlohmann::json::dump() gives for the same values (the
// format clients and tests know), without building a JSON tree: a world with 100k walls is
// written in one pass.
void append_int(std::string& out, std::int64_t v) {
  char buf[24];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

void append_string(std::string& out, const std::string& s) {
  for (unsigned char c : s)
    if (c < 0x20 || c == '"' || c == '\\' || c >= 0x80) {
      out += json(s).dump();  // escapes (and UTF-8 checks) exactly as before
      return;
    }
  out += '"';
  out += s;
  out += '"';
}

void append_point(std::string& out, const Cell& c, int dims) {
  out += '[';
  append_int(out, c.x);
  out += ',';
  append_int(out, c.y);
  if (dims == 3) {
    out += ',';
    append_int(out, c.z);
  }
  out += ']';
}

void append_points(std::string& out, const std::vector<Cell>& points, int dims) {
  out += '[';
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i != 0) out += ',';
    append_point(out, points[i], dims);
  }
  out += ']';
}

}  // namespace

std::string points_json(const std::vector<Cell>& points, int dims) {
  std::string out;
  out.reserve(points.size() * (dims == 3 ? 14 : 10) + 2);
  append_points(out, points, dims);
  return out;
}

void append_items_json(std::string& out, const WorldState& state, int dims) {
  out += '[';
  for (std::size_t i = 0; i < state.items.size(); ++i) {
    const auto& li = state.items[i];
    out += i == 0 ? "{\"id\":" : ",{\"id\":";
    append_int(out, li.item.id);
    out += ",\"x\":";
    append_int(out, li.at.x);
    out += ",\"y\":";
    append_int(out, li.at.y);
    if (dims == 3) {
      out += ",\"z\":";
      append_int(out, li.at.z);
    }
    out += ",\"color\":";
    append_string(out, li.item.color);
    out += ",\"shape\":";
    append_string(out, li.item.shape);
    out += '}';
  }
  out += ']';
}

void append_robot_json(std::string& out, const WorldState& state, int dims) {
  out += "{\"x\":";
  append_int(out, state.robot.x);
  out += ",\"y\":";
  append_int(out, state.robot.y);
  if (dims == 3) {
    out += ",\"z\":";
    append_int(out, state.robot.z);
  }
  out += ",\"holding\":[";
  for (std::size_t i = 0; i < state.held.size(); ++i) {
    const auto& h = state.held[i];
    out += i == 0 ? "{\"id\":" : ",{\"id\":";
    append_int(out, h.id);
    out += ",\"color\":";
    append_string(out, h.color);
    out += ",\"shape\":";
    append_string(out, h.shape);
    out += '}';
  }
  out += "]}";
}

std::string write_world(const WorldState& state, const std::vector<RawField>& fields) {
  if (!state.geometry) throw Error(codes::kInternal, "write_world: the state has no geometry");
  const int dims = state.geometry->dims();
  std::size_t size = 256 + state.items.size() * 64;
  for (const auto& f : fields) size += f.key.size() + f.json.size() + 4;
  std::string out;
  out.reserve(size);
  out += '{';
  std::vector<std::string> written;  // a repeated field keeps its first place, last value wins
  std::vector<std::string> values;
  for (const auto& f : fields) {
    // Validated without building a tree; written compactly as dump() would.
    if (!json::accept(f.json))
      throw Error(codes::kInternal, "write_world: field \"" + f.key + "\" is not JSON text");
    const bool compact = f.json.find_first_of(" \t\r\n") == std::string::npos;
    std::string text = compact ? f.json : json::parse(f.json).dump();
    auto at = std::find(written.begin(), written.end(), f.key);
    if (at != written.end()) {
      values[static_cast<std::size_t>(at - written.begin())] = std::move(text);
    } else {
      written.push_back(f.key);
      values.push_back(std::move(text));
    }
  }
  for (std::size_t i = 0; i < written.size(); ++i) {
    append_string(out, written[i]);
    out += ':';
    out += values[i];
    out += ',';
  }
  out += "\"items\":";
  append_items_json(out, state, dims);
  out += ",\"robot\":";
  append_robot_json(out, state, dims);
  out += ",\"rooms\":{";
  if (state.rooms) {
    bool first = true;
    for (const auto& [name, area] : *state.rooms) {
      if (!first) out += ',';
      first = false;
      append_string(out, name);
      out += ':';
      append_points(out, area, dims);
    }
  }
  out += "},\"bounds\":{\"min\":";
  append_point(out, state.geometry->min(), dims);
  out += ",\"max\":";
  append_point(out, state.geometry->max(), dims);
  out += "}}";
  return out;
}

}  // namespace world_format

OtherDimsError::OtherDimsError(int world_dims, const std::string& message)
    : Error(codes::kBadWorld, message), world_dims_(world_dims) {}
OtherDimsError::~OtherDimsError() = default;

void World::do_save_items(std::string& out, const WorldState& state) const {
  world_format::append_items_json(out, state, state.geometry ? state.geometry->dims() : dims());
}

void World::do_save_robot(std::string& out, const WorldState& state) const {
  world_format::append_robot_json(out, state, state.geometry ? state.geometry->dims() : dims());
}

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk

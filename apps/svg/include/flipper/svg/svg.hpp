#pragma once
/// @file svg.hpp
/// SVG drawing of the world pictures: a small element writer (no
/// external tool, no scripting: plain SVG 1.1 any browser, paper or bug tracker shows), and the
/// picture of a world with a plan drawn on it (`flipper run --svg FILE`, `repl :save FILE`).
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace flipper::svg {

/// Text safe inside SVG elements and attributes.
std::string escape(const std::string& text);
/// A coordinate with one decimal ("12.5").
std::string num(double v);

/// Appends SVG elements; `str()` closes the document. Coordinates in pixels, y downwards.
class Writer {
 public:
  Writer(double width, double height, int font_size = 12);
  void rect(double x, double y, double w, double h, const std::string& fill,
            const std::string& stroke = "none");
  void line(double x1, double y1, double x2, double y2, const std::string& stroke,
            double width = 1);
  void circle(double cx, double cy, double r, const std::string& fill,
              const std::string& stroke = "none");
  void polyline(const std::vector<std::pair<double, double>>& points, const std::string& stroke,
                double width);
  /// anchor: start | middle | end.
  void text(double x, double y, const std::string& text, const std::string& anchor = "start",
            int size = 0, const std::string& fill = "black");
  /// A raw element (for what the helpers above do not cover).
  void raw(const std::string& element) { body_ << element << '\n'; }
  std::string str() const;

 private:
  double width_, height_;
  int font_size_;
  std::ostringstream body_;
};

/// A cell of the protocol, `[x, y]`, `[x, y, z]` or `{x, y, z}` (missing coordinates are 0); the
/// world picture and the repl's text map both read cells this way.
struct Pt {
  int x = 0, y = 0, z = 0;
};
Pt point_of(const nlohmann::json& p);

/// The world (protocol world object, 2-D or one floor of 3-D) as a picture: walls, rooms
/// (labelled), items (coloured shapes, stacks counted), the robot; with `trace` (protocol trace
/// steps) the path from `start` as a line, its end, picks and drops. Title on top, a legend
/// below. 3-D worlds show the floor of the robot's z (or of the path's end).
std::string world_picture(const nlohmann::json& world, const nlohmann::json* trace,
                          const std::string& title);

}  // namespace flipper::svg

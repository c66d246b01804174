// The SVG element writer.
#include <cstdio>

#include "flipper/svg/svg.hpp"

namespace flipper::svg {

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

Writer::Writer(double width, double height, int font_size)
    : width_(width), height_(height), font_size_(font_size) {}

void Writer::rect(double x, double y, double w, double h, const std::string& fill,
                  const std::string& stroke) {
  body_ << "<rect x=\"" << num(x) << "\" y=\"" << num(y) << "\" width=\"" << num(w)
        << "\" height=\"" << num(h) << "\" fill=\"" << fill << "\" stroke=\"" << stroke << "\"/>\n";
}

void Writer::line(double x1, double y1, double x2, double y2, const std::string& stroke,
                  double width) {
  body_ << "<line x1=\"" << num(x1) << "\" y1=\"" << num(y1) << "\" x2=\"" << num(x2) << "\" y2=\""
        << num(y2) << "\" stroke=\"" << stroke << "\" stroke-width=\"" << num(width) << "\"/>\n";
}

void Writer::circle(double cx, double cy, double r, const std::string& fill,
                    const std::string& stroke) {
  body_ << "<circle cx=\"" << num(cx) << "\" cy=\"" << num(cy) << "\" r=\"" << num(r)
        << "\" fill=\"" << fill << "\" stroke=\"" << stroke << "\"/>\n";
}

void Writer::polyline(const std::vector<std::pair<double, double>>& points,
                      const std::string& stroke, double width) {
  body_ << "<polyline fill=\"none\" stroke=\"" << stroke << "\" stroke-width=\"" << num(width)
        << "\" stroke-linejoin=\"round\" points=\"";
  for (const auto& [x, y] : points) body_ << num(x) << ',' << num(y) << ' ';
  body_ << "\"/>\n";
}

void Writer::text(double x, double y, const std::string& text, const std::string& anchor, int size,
                  const std::string& fill) {
  body_ << "<text x=\"" << num(x) << "\" y=\"" << num(y) << "\" text-anchor=\"" << anchor << '"';
  if (size > 0) body_ << " font-size=\"" << size << '"';
  if (fill != "black") body_ << " fill=\"" << fill << '"';
  body_ << '>' << escape(text) << "</text>\n";
}

std::string Writer::str() const {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(width_) + "\" height=\"" +
         num(height_) + "\" viewBox=\"0 0 " + num(width_) + " " + num(height_) +
         "\" font-family=\"sans-serif\" font-size=\"" + std::to_string(font_size_) + "\">\n" +
         "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n" + body_.str() + "</svg>\n";
}

}  // namespace flipper::svg

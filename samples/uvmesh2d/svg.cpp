#include "uvmesh2d/svg.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "uvmesh2d/text.h"

namespace uvmesh::cli2d {

namespace {

constexpr std::size_t kClasses = std::size(kSvgQualityBounds) + 1;
// Green (good) to red (bad), one per quality class.
constexpr std::array<const char*, kClasses> kColors = {"#1a9850", "#66bd63", "#a6d96a", "#fee08b",
                                                       "#fdae61", "#f46d43", "#d73027"};

std::size_t quality_class(double q) {
  if (!(q == q)) return kClasses - 1;  // NaN: a degenerate triangle, worst class
  std::size_t k = 0;
  while (k < std::size(kSvgQualityBounds) && q >= kSvgQualityBounds[k]) ++k;
  return k;
}

std::string escape(const std::string& s) {
  std::string r;
  for (char c : s) {
    switch (c) {
      case '<':
        r += "&lt;";
        break;
      case '>':
        r += "&gt;";
        break;
      case '&':
        r += "&amp;";
        break;
      case '"':
        r += "&quot;";
        break;
      default:
        r += c;
    }
  }
  return r;
}

}  // namespace

void write_svg(std::ostream& out, const m2d::Mesh& m, const SvgOptions& opt) {
  std::string b;
  b.reserve(1 << 20);
  auto flush = [&](bool force) { text::flush_buffer(out, b, force); };

  // Fit: the longer side of the bounding box becomes opt.size units.
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  for (const m2d::Vec2& v : m.vertices) {
    xmin = std::min(xmin, v.x);
    xmax = std::max(xmax, v.x);
    ymin = std::min(ymin, v.y);
    ymax = std::max(ymax, v.y);
  }
  if (m.vertices.empty()) xmin = ymin = 0, xmax = ymax = 1;
  const double span = std::max({xmax - xmin, ymax - ymin, 1e-300});
  const double s = opt.size / span;
  const double margin = 0.02 * opt.size;
  const double W = (xmax - xmin) * s + 2 * margin;
  const double H = (ymax - ymin) * s + 2 * margin;
  const bool legend = !opt.quality.empty() && opt.quality.size() == m.triangles.size();
  const double font = 0.018 * opt.size;
  const std::size_t nt = m.triangles.size();
  const bool fill = nt <= opt.max_filled_triangles;
  const bool wire = nt <= opt.max_wireframe_triangles;
  const bool caption = !fill || !opt.title.empty();
  const double footer = (legend ? 2.6 : 0.0) * font + (caption ? 1.6 * font : 0.0) +
                        (legend || caption ? 0.4 * font : 0.0);
  const int decimals = m.triangles.size() <= 20'000 ? 2 : 1;
  auto X = [&](double x) { return margin + (x - xmin) * s; };
  auto Y = [&](double y) { return margin + (ymax - y) * s; };  // y up
  auto point = [&](const m2d::Vec2& v) {
    text::append_fixed(b, X(v.x), decimals);
    b += ' ';
    text::append_fixed(b, Y(v.y), decimals);
  };

  b += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" "
       "viewBox=\"0 0 ";
  text::append_fixed(b, W, 1);
  b += ' ';
  text::append_fixed(b, H + footer, 1);
  b += "\" width=\"";
  text::append_fixed(b, W, 0);
  b += "\" height=\"";
  text::append_fixed(b, H + footer, 0);
  b += "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";

  if (fill) {
    b += "<g stroke-linejoin=\"round\"";
    if (wire) {
      b += " stroke=\"#202020\" stroke-width=\"";
      // Thin enough not to hide small triangles: a fraction of the mean triangle size.
      const double mean_side =
          opt.size / std::sqrt(static_cast<double>(std::max<std::size_t>(nt, 1)));
      text::append_fixed(b, std::clamp(0.04 * mean_side, 0.02, 0.6), 2);
      b += '"';
    }
    b += ">\n";
    // One path per colour class.
    std::vector<std::size_t> cls(nt, 0);
    if (legend)
      for (std::size_t i = 0; i < nt; ++i) cls[i] = quality_class(opt.quality[i]);
    for (std::size_t k = 0; k < (legend ? kClasses : 1); ++k) {
      bool open = false;
      for (std::size_t i = 0; i < nt; ++i) {
        if (cls[i] != k) continue;
        if (!open) {
          b += "<path fill=\"";
          b += legend ? kColors[k] : "#d0d0d0";
          b += "\" d=\"";
          open = true;
        }
        const auto& t = m.triangles[i];
        b += 'M';
        point(m.vertices[static_cast<std::size_t>(t[0])]);
        b += ' ';
        point(m.vertices[static_cast<std::size_t>(t[1])]);
        b += ' ';
        point(m.vertices[static_cast<std::size_t>(t[2])]);
        b += 'Z';
        flush(false);
      }
      if (open) b += "\"/>\n";
    }
    b += "</g>\n";
  }

  // Boundary edges, thick.
  if (!m.boundary_edges.empty()) {
    b += "<path fill=\"none\" stroke=\"black\" stroke-linecap=\"round\" stroke-width=\"";
    text::append_fixed(b, 0.003 * opt.size, 2);
    b += "\" d=\"";
    for (const m2d::BoundaryEdge& e : m.boundary_edges) {
      b += 'M';
      point(m.vertices[static_cast<std::size_t>(e.a)]);
      b += ' ';
      point(m.vertices[static_cast<std::size_t>(e.b)]);
      flush(false);
    }
    b += "\"/>\n";
  }

  // Legend and caption below the picture.
  double y = H + 1.2 * font;
  b += "<g font-family=\"sans-serif\" font-size=\"";
  text::append_fixed(b, font, 1);
  b += "\">\n";
  if (legend) {
    double x = margin;
    const double box = font;
    for (std::size_t k = 0; k < kClasses; ++k) {
      std::string label = k == 0 ? "Q<" : k + 1 == kClasses ? "Q\xe2\x89\xa5" : "";
      if (k == 0) {
        text::append_double(label, kSvgQualityBounds[0]);
      } else if (k + 1 == kClasses) {
        text::append_double(label, kSvgQualityBounds[k - 1]);
      } else {
        text::append_double(label, kSvgQualityBounds[k - 1]);
        label += "\xe2\x80\x93";  // en dash
        text::append_double(label, kSvgQualityBounds[k]);
      }
      b += "<rect x=\"";
      text::append_fixed(b, x, 1);
      b += "\" y=\"";
      text::append_fixed(b, y - 0.85 * box, 1);
      b += "\" width=\"";
      text::append_fixed(b, box, 1);
      b += "\" height=\"";
      text::append_fixed(b, box, 1);
      b += "\" fill=\"";
      b += kColors[k];
      b += "\"/><text x=\"";
      text::append_fixed(b, x + 1.3 * box, 1);
      b += "\" y=\"";
      text::append_fixed(b, y, 1);
      b += "\">" + escape(label) + "</text>\n";
      x += box * (1.8 + 0.62 * static_cast<double>(label.size()));
    }
    y += 1.4 * font;
  }
  if (caption) {
    std::string line = opt.title;
    if (!fill)
      line += (line.empty() ? "" : " -- ") + std::to_string(nt) +
              " triangles: only the boundary is drawn";
    b += "<text x=\"";
    text::append_fixed(b, margin, 1);
    b += "\" y=\"";
    text::append_fixed(b, y + 0.2 * font, 1);
    b += "\">" + escape(line) + "</text>\n";
  }
  b += "</g>\n</svg>\n";
  flush(true);
}

}  // namespace uvmesh::cli2d

// SVG pictures for the report (report.h): histograms and a face's (u,v) mesh. Plain SVG
// 1.1 text, viewable in any browser; numbers through std::to_chars like the writers.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

#include "uvmesh/io/report.h"

namespace uvmesh::io {

namespace {

std::string num(double v) {
  char buf[32];
  // Three decimals are enough for screen coordinates and labels.
  // + 0.0 turns -0 into 0.
  const auto r = std::to_chars(buf, buf + sizeof buf, std::round(v * 1000.0) / 1000.0 + 0.0);
  return std::string(buf, r.ptr);
}

std::string escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '&')
      o += "&amp;";
    else if (c == '"')
      o += "&quot;";
    else
      o += c;
  }
  return o;
}

std::string text(double x, double y, const std::string& s, const char* anchor = "middle",
                 int size = 12) {
  return "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\" font-family=\"sans-serif\" font-size=\"" +
         std::to_string(size) + "\" text-anchor=\"" + anchor + "\">" + escape(s) + "</text>\n";
}

// Shape quality q in [0,1] -> red (poor) .. yellow .. green (equilateral).
std::string q_color(double q) {
  q = std::clamp(q, 0.0, 1.0);
  const int r = static_cast<int>(std::lround(255 * std::min(1.0, 2.0 * (1.0 - q))));
  const int g = static_cast<int>(std::lround(200 * std::min(1.0, 2.0 * q)));
  return "rgb(" + std::to_string(r) + "," + std::to_string(g) + ",60)";
}

}  // namespace

std::string histogram_svg(const Histogram& h, const std::string& title,
                          const std::string& x_label) {
  constexpr double W = 640, H = 360, L = 60, R = 20, T = 40, B = 60;
  const std::size_t n = h.count.size();
  const std::size_t top = n == 0 ? 0 : *std::max_element(h.count.begin(), h.count.end());
  std::size_t total = 0;
  for (std::size_t c : h.count) total += c;
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(W) + "\" height=\"" +
                  num(H) + "\" viewBox=\"0 0 " + num(W) + " " + num(H) +
                  "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s += text(W / 2, 24, title + " (" + std::to_string(total) + " values)", "middle", 15);
  const double pw = W - L - R, ph = H - T - B;
  s += "<line x1=\"" + num(L) + "\" y1=\"" + num(T + ph) + "\" x2=\"" + num(L + pw) + "\" y2=\"" +
       num(T + ph) + "\" stroke=\"black\"/>\n<line x1=\"" + num(L) + "\" y1=\"" + num(T) +
       "\" x2=\"" + num(L) + "\" y2=\"" + num(T + ph) + "\" stroke=\"black\"/>\n";
  s += text(L - 6, T + 4, std::to_string(top), "end", 11);
  s += text(L - 6, T + ph, "0", "end", 11);
  const double bw = n > 0 ? pw / static_cast<double>(n) : pw;
  for (std::size_t i = 0; i < n; ++i) {
    const double hgt =
        top > 0 ? ph * static_cast<double>(h.count[i]) / static_cast<double>(top) : 0.0;
    const double x = L + bw * static_cast<double>(i);
    s += "<rect x=\"" + num(x + 1) + "\" y=\"" + num(T + ph - hgt) + "\" width=\"" +
         num(std::max(bw - 2, 1.0)) + "\" height=\"" + num(hgt) + "\" fill=\"#4a7ab5\"><title>[" +
         num(h.lo[i]) + ", " +
         (i + 1 < n ? num(h.lo[i + 1]) : (std::isfinite(h.hi) ? num(h.hi) : std::string("inf"))) +
         "): " + std::to_string(h.count[i]) + "</title></rect>\n";
    // Label every bin's lower end when there is room, else every other one.
    if (n <= 20 || i % 2 == 0) s += text(x, T + ph + 16, num(h.lo[i]), "middle", 10);
  }
  if (n > 0)
    s += text(L + pw, T + ph + 16, std::isfinite(h.hi) ? num(h.hi) : std::string("inf"), "middle",
              10);
  s += text(L + pw / 2, H - 18, x_label);
  s += "</svg>\n";
  return s;
}

std::string face_uv_svg(const surface::SurfaceMesh& m, geom::Id face) {
  if (m.triangle_uv.size() != m.triangles.size()) return "";
  geom::Vec2 lo(std::numeric_limits<double>::infinity()),
      hi(-std::numeric_limits<double>::infinity());
  std::size_t count = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    if (m.triangle_face[t] != face) continue;
    ++count;
    for (const geom::Vec2& uv : m.triangle_uv[t]) lo = glm::min(lo, uv), hi = glm::max(hi, uv);
  }
  if (count == 0) return "";
  constexpr double S = 800, M = 40;
  // Equal scales in u and v: the picture shows the (u,v) domain's true shape, which is
  // where an anisotropic mesh shows its stretching.
  const double span = std::max({hi.x - lo.x, hi.y - lo.y, 1e-300});
  const double k = (S - 2 * M) / span;
  // At least 640 wide so that the caption fits a narrow domain; the domain is centred.
  const double w = std::max((hi.x - lo.x) * k + 2 * M, 640.0), h = (hi.y - lo.y) * k + 2 * M + 30;
  const double x0 = 0.5 * (w - (hi.x - lo.x) * k);
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(w) + "\" height=\"" +
                  num(h) + "\" viewBox=\"0 0 " + num(w) + " " + num(h) +
                  "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s += text(w / 2, 20,
            "face " + std::to_string(face) + ": " + std::to_string(count) +
                " triangles in (u,v), colour = 3D shape quality q (red = poor)",
            "middle", 13);
  s += "<g stroke=\"black\" stroke-width=\"0.4\" stroke-linejoin=\"round\">\n";
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    if (m.triangle_face[t] != face) continue;
    const auto& tri = m.triangles[t];
    const double Q = surface::triangle_Q(m.points[static_cast<std::size_t>(tri[0])],
                                         m.points[static_cast<std::size_t>(tri[1])],
                                         m.points[static_cast<std::size_t>(tri[2])]);
    s += "<polygon points=\"";
    for (const geom::Vec2& uv : m.triangle_uv[t])
      s += num(x0 + (uv.x - lo.x) * k) + "," + num(30 + M + (hi.y - uv.y) * k) + " ";  // v up
    s += "\" fill=\"" + q_color(std::isfinite(Q) && Q > 0 ? 1.0 / Q : 0.0) + "\"/>\n";
  }
  s += "</g>\n";
  s += text(M, h - 8,
            "u [" + num(lo.x) + ", " + num(hi.x) + "]  v [" + num(lo.y) + ", " + num(hi.y) + "]",
            "start", 11);
  s += "</svg>\n";
  return s;
}

}  // namespace uvmesh::io

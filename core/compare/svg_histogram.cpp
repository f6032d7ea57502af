#include "compare/svg_histogram.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "mesh/number_text.h"

namespace vd::compare {
namespace {

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

std::string fmt(const char* f, double x) { return number_text(x, f); }

}  // namespace

std::string histogram_svg(const std::string& title, const std::vector<HistogramPanel>& panels, int columns) {
  columns = std::max(columns, 1);
  const int rows = static_cast<int>((panels.size() + columns - 1) / columns);
  const double pw = 420, ph = 260, top = 40;         // panel size, title band
  const double ml = 50, mr = 15, mt = 34, mb = 40;   // plot margins inside a panel
  const double W = pw * columns, H = top + ph * rows;
  // One vertical scale for all panels: the largest share of any bin.
  double peak = 0;
  for (const auto& p : panels) {
    long total = 0;
    for (long c : p.bins) total += c;
    if (total > 0)
      for (long c : p.bins) peak = std::max(peak, double(c) / total);
  }
  if (peak <= 0) peak = 1;
  peak *= 1.1;

  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W
    << ' ' << H << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  s << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s << "<text x=\"" << W / 2 << "\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">" << escape(title) << "</text>\n";
  for (size_t i = 0; i < panels.size(); ++i) {
    const HistogramPanel& p = panels[i];
    const double x0 = pw * (i % columns), y0 = top + ph * (i / columns);
    const double px = x0 + ml, py = y0 + mt, w = pw - ml - mr, h = ph - mt - mb;
    s << "<g>\n<text x=\"" << x0 + pw / 2 << "\" y=\"" << y0 + 16 << "\" text-anchor=\"middle\" font-size=\"13\">"
      << escape(p.title) << "</text>\n";
    s << "<rect x=\"" << px << "\" y=\"" << py << "\" width=\"" << w << "\" height=\"" << h
      << "\" fill=\"none\" stroke=\"#888\"/>\n";
    // Axes: angle ticks every 30 degrees, share ticks at quarters of the peak.
    for (int a = 0; a <= 180; a += 30) {
      const double x = px + w * a / 180.0;
      s << "<line x1=\"" << x << "\" y1=\"" << py + h << "\" x2=\"" << x << "\" y2=\"" << py + h + 4
        << "\" stroke=\"#888\"/><text x=\"" << x << "\" y=\"" << py + h + 15 << "\" text-anchor=\"middle\">" << a
        << "</text>\n";
    }
    s << "<text x=\"" << px + w / 2 << "\" y=\"" << py + h + 30 << "\" text-anchor=\"middle\">dihedral angle (degrees)</text>\n";
    for (int q = 1; q <= 4; ++q) {
      const double v = peak / 1.1 * q / 4, y = py + h - h * v / peak;
      s << "<line x1=\"" << px - 4 << "\" y1=\"" << y << "\" x2=\"" << px << "\" y2=\"" << y
        << "\" stroke=\"#888\"/><text x=\"" << px - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">"
        << fmt("%.1f%%", 100 * v) << "</text>\n";
    }
    if (!p.has_data) {
      s << "<text x=\"" << px + w / 2 << "\" y=\"" << py + h / 2 << "\" text-anchor=\"middle\" fill=\"#b00\">"
        << escape(p.note.substr(0, 70)) << "</text>\n</g>\n";
      continue;
    }
    long total = 0;
    for (long c : p.bins) total += c;
    const double bw = w / p.bins.size();
    for (size_t b = 0; b < p.bins.size(); ++b) {
      if (p.bins[b] == 0 || total == 0) continue;
      const double bh = h * (double(p.bins[b]) / total) / peak;
      s << "<rect x=\"" << fmt("%.2f", px + b * bw) << "\" y=\"" << fmt("%.2f", py + h - bh) << "\" width=\""
        << fmt("%.2f", bw) << "\" height=\"" << fmt("%.2f", bh) << "\" fill=\"" << (i % columns ? "#d9822b" : "#3a6fb0")
        << "\"/>\n";
    }
    for (double a : {p.min_deg, p.max_deg}) {
      const double x = px + w * std::clamp(a, 0.0, 180.0) / 180.0;
      s << "<line x1=\"" << fmt("%.2f", x) << "\" y1=\"" << py << "\" x2=\"" << fmt("%.2f", x) << "\" y2=\"" << py + h
        << "\" stroke=\"#c00\" stroke-dasharray=\"3,2\"/>\n";
    }
    s << "<text x=\"" << px + w - 4 << "\" y=\"" << py + 14 << "\" text-anchor=\"end\">"
      << escape(fmt("min %.2f", p.min_deg) + fmt(" / max %.2f deg", p.max_deg)) << "</text>\n";
    s << "<text x=\"" << px + w - 4 << "\" y=\"" << py + 28 << "\" text-anchor=\"end\">" << p.tets
      << " tetrahedra</text>\n</g>\n";
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace vd::compare

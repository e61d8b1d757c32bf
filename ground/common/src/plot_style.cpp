// plot_style.cpp: the palette and the gnuplot quoting (plot_style.hpp).
#include "sinkwatch/ground/plot_style.hpp"

#include <cstdio>

namespace sinkwatch {
namespace ground {

namespace {

// Six colours at least 38 apart (CIE76 delta E) from each other and from
// every grey of the levels; the previous gnuplot defaults put LR and RR
// (sky blue, blue) 26 apart and gave RF the caution level's orange.
constexpr std::array<PlotLineStyle, kPlotWheels> kWheels{{
    {1, "wheel LF", "#1f77b4", 1.5, 1, 0},  // blue
    {2, "wheel LM", "#2ca02c", 1.5, 1, 0},  // green
    {3, "wheel LR", "#9467bd", 1.5, 1, 0},  // purple
    {4, "wheel RF", "#d62728", 1.5, 1, 0},  // red
    {5, "wheel RM", "#17becf", 1.5, 1, 0},  // cyan
    {6, "wheel RR", "#ff7f0e", 1.5, 1, 0},  // orange
}};

constexpr std::array<PlotLineStyle, kPlotLevels> kLevels{{
    {11, "stop level, stop marker, rover stop", "#000000", 2.0, 1, 0},
    {12, "caution level", "#808080", 2.0, 2, 0},
    {13, "I_max of every wheel", "#404040", 1.0, 2, 0},
    {14, "simulator: deepest wheel", "#606060", 2.0, 4, 0},
    {15, "simulated embedding marker", "#000000", 1.5, 3, 0},
    {16, "worst wheel state", "#a0a0a0", 3.0, 1, 0},
    {17, "escape command", "#404040", 1.0, 5, 0},
}};

constexpr std::array<PlotLineStyle, 2> kSamples{{
    {21, "training rows (open circles)", "#1f77b4", 1.0, 1, 6},
    {22, "held-out rows (filled circles)", "#d62728", 1.0, 1, 7},
}};

std::string set_linetype(const PlotLineStyle& s) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "set linetype %d lc rgb '%s' lw %g dt %d", s.linetype, s.colour, s.width, s.dash);
  std::string line = buf;
  if (s.point != 0) {
    line += " pt " + std::to_string(s.point);
  }
  return line + "  # " + s.name + "\n";
}

}  // namespace

const std::array<PlotLineStyle, kPlotWheels>& wheel_plot_styles() { return kWheels; }

int wheel_linetype(std::size_t wheel) { return kWheels.at(wheel).linetype; }

const std::array<PlotLineStyle, kPlotLevels>& level_plot_styles() { return kLevels; }

int level_linetype(PlotLevel level) { return kLevels.at(static_cast<std::size_t>(level)).linetype; }

const PlotLineStyle& sample_plot_style(PlotSample sample) { return kSamples.at(static_cast<std::size_t>(sample)); }

int sample_linetype(PlotSample sample) { return sample_plot_style(sample).linetype; }

std::string gnuplot_linetypes() {
  std::string out = "# the sinkwatch palette (ground/common/include/sinkwatch/ground/plot_style.hpp)\n";
  for (const PlotLineStyle& s : kWheels) {
    out += set_linetype(s);
  }
  for (const PlotLineStyle& s : kLevels) {
    out += set_linetype(s);
  }
  for (const PlotLineStyle& s : kSamples) {
    out += set_linetype(s);
  }
  return out;
}

std::string quote_gnuplot_string(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    if (ch == '\'') {
      out += "''";
    } else if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) {
      out += ' ';
    } else {
      out += ch;
    }
  }
  return out;
}

std::string escape_gnuplot_text(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 8);
  for (const char ch : text) {
    switch (ch) {
      case '_':
      case '^':
      case '@':
      case '&':
      case '~':
      case '{':
      case '}':
      case '\\':
        out += '\\';
        out += ch;
        break;
      default:
        out += quote_gnuplot_string(std::string_view(&ch, 1));
    }
  }
  return out;
}

}  // namespace ground
}  // namespace sinkwatch

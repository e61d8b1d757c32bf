// plot_style.hpp: the one palette of the gnuplot plots the ground tools write
// (`sinkwatch replay --plot`, `sinkwatch diagnose --report`), and the quoting
// of user strings (file names, channel names) in gnuplot scripts.
//
// Every line of a plot is drawn with `lt N` and nothing else (no `lc`, `dt` or
// `lw` on the plot command), N one of the linetypes below, so that a legend
// key always looks like the line it names. The six wheels (LF, LM, LR, RF, RM,
// RR) get six clearly distinct colours; levels, thresholds and markers (stop,
// caution, I_max, the simulator's truth, ...) are black or grey with their own
// dash types, so no level can be taken for a wheel. Two more linetypes are
// for the diagnosis's data points (training and held-out rows).
#ifndef SINKWATCH_GROUND_PLOT_STYLE_HPP
#define SINKWATCH_GROUND_PLOT_STYLE_HPP

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

namespace sinkwatch {
namespace ground {

struct PlotLineStyle {
  int linetype;        // gnuplot `set linetype` index, used as `lt N`
  const char* name;    // what it draws (also written as a comment in the script)
  const char* colour;  // "#rrggbb"
  double width;        // line width
  int dash;            // gnuplot dash type: 1 solid, 2 dashed, 3 dotted, 4 dash-dot, 5 dash-dot-dot
  int point;           // gnuplot point type for `with points` (0: the style draws lines only)
};

inline constexpr std::size_t kPlotWheels = 6;

/// One style per wheel, in the telemetry's wheel order LF, LM, LR, RF, RM, RR;
/// linetypes 1 to 6.
[[nodiscard]] const std::array<PlotLineStyle, kPlotWheels>& wheel_plot_styles();
[[nodiscard]] int wheel_linetype(std::size_t wheel);

/// Levels, thresholds and markers: black and greys, told apart by dash type
/// and width; linetypes from 11.
enum class PlotLevel {
  stop,           // the stop level, the stop marker, the rover's stop-and-re-plan
  caution,        // the caution level
  current_limit,  // I_max of every wheel
  truth,          // the simulator's deepest wheel
  embedding,      // the simulated embedding marker
  state,          // the worst wheel state
  escape,         // the escape command
};
inline constexpr std::size_t kPlotLevels = 7;
[[nodiscard]] const std::array<PlotLineStyle, kPlotLevels>& level_plot_styles();
[[nodiscard]] int level_linetype(PlotLevel level);

/// Data points of the diagnosis: training rows and held-out rows (linetypes 21, 22).
enum class PlotSample { training, held_out };
[[nodiscard]] const PlotLineStyle& sample_plot_style(PlotSample sample);
[[nodiscard]] int sample_linetype(PlotSample sample);

/// The `set linetype` lines that define every style above, one per line.
[[nodiscard]] std::string gnuplot_linetypes();

/// `text` for use inside a single-quoted gnuplot string that is drawn as
/// enhanced text (a title, a label): the enhanced-text control characters
/// _ ^ @ & ~ { } and the backslash are escaped with a backslash, a single
/// quote is doubled, and line breaks and other control characters become
/// spaces. "x_y.csv" is then drawn as x_y.csv, not as x with a subscript y.
[[nodiscard]] std::string escape_gnuplot_text(std::string_view text);

/// `text` as the inside of a single-quoted gnuplot string taken literally
/// (a file name for `set output`, or a title drawn `noenhanced`): a single
/// quote is doubled, line breaks and other control characters become spaces.
[[nodiscard]] std::string quote_gnuplot_string(std::string_view text);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_PLOT_STYLE_HPP

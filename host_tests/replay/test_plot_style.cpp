// The replay plot's gnuplot script (issue 17): one palette with six clearly
// distinct wheel colours apart from the levels' colours, legend keys that
// look like their lines, and user text (the log's file name) escaped in the
// title. The script is read as text from plot_script(), the function
// `sinkwatch replay --plot` draws with; one test also runs gnuplot on it.
#include "sinkwatch/ground/plot_style.hpp"
#include "sinkwatch/ground/replay_command.hpp"
#include "sinkwatch/ground/replay_report.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace sg = sinkwatch::ground;
namespace fs = std::filesystem;

namespace {

// ---- a small reader of the generated script ----

struct Clause {
  std::string text;                  // the clause with its quoted strings blanked
  std::optional<int> linetype;       // lt N
  std::optional<std::string> title;  // t '...' / title '...'; nullopt: notitle
};

struct Script {
  std::map<int, std::string> colour;   // set linetype N lc rgb '#rrggbb'
  std::vector<std::vector<Clause>> plots;
  std::vector<std::string> lines;
};

// Splits at commas outside quotes and parentheses.
std::vector<std::string> split_clauses(const std::string& s) {
  std::vector<std::string> out(1);
  int depth = 0;
  char quote = 0;
  for (char ch : s) {
    if (quote != 0) {
      if (ch == quote) quote = 0;
    } else if (ch == '\'' || ch == '"') {
      quote = ch;
    } else if (ch == '(') {
      ++depth;
    } else if (ch == ')') {
      --depth;
    } else if (ch == ',' && depth == 0) {
      out.emplace_back();
      continue;
    }
    out.back() += ch;
  }
  return out;
}

std::string blank_quotes(const std::string& s) {
  std::string out;
  char quote = 0;
  for (char ch : s) {
    if (quote != 0) {
      if (ch == quote) quote = 0;
      out += quote != 0 ? '_' : ch;
    } else {
      if (ch == '\'' || ch == '"') quote = ch;
      out += ch;
    }
  }
  return out;
}

Script read_script(const std::string& text) {
  Script sc;
  std::istringstream in(text);
  std::string line;
  const std::regex set_lt(R"(^set linetype (\d+) lc rgb '(#[0-9a-fA-F]{6})')");
  const std::regex lt(R"(\blt (\d+)\b)");
  const std::regex title(R"(\b(?:t|title) '([^']*)')");
  bool in_data = false;
  while (std::getline(in, line)) {
    if (in_data) {
      in_data = line != "EOD";
      continue;
    }
    if (line.find("<< EOD") != std::string::npos) {
      in_data = true;
      continue;
    }
    sc.lines.push_back(line);
    std::smatch m;
    if (std::regex_search(line, m, set_lt)) sc.colour[std::stoi(m[1])] = m[2];
    if (line.rfind("plot ", 0) != 0) continue;
    std::vector<Clause> plot;
    for (const std::string& raw : split_clauses(line.substr(5))) {
      Clause c;
      c.text = blank_quotes(raw);
      if (std::regex_search(c.text, m, lt)) c.linetype = std::stoi(m[1]);
      if (std::regex_search(raw, m, title)) c.title = m[1];
      plot.push_back(c);
    }
    sc.plots.push_back(plot);
  }
  return sc;
}

// ---- colour distance (CIE76 delta E in CIELAB, D65) ----

std::array<double, 3> lab(const std::string& hex) {
  std::array<double, 3> rgb{};
  for (int i = 0; i < 3; ++i) {
    double c = std::stoi(hex.substr(1 + 2 * i, 2), nullptr, 16) / 255.0;
    rgb[i] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  }
  const double x = (0.4124 * rgb[0] + 0.3576 * rgb[1] + 0.1805 * rgb[2]) / 0.95047;
  const double y = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
  const double z = (0.0193 * rgb[0] + 0.1192 * rgb[1] + 0.9505 * rgb[2]) / 1.08883;
  const auto f = [](double t) { return t > 0.008856 ? std::cbrt(t) : 7.787 * t + 16.0 / 116.0; };
  return {116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))};
}

double delta_e(const std::string& a, const std::string& b) {
  const std::array<double, 3> p = lab(a);
  const std::array<double, 3> q = lab(b);
  return std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
}

// Two colours at least this far apart are told apart at a glance; gnuplot's
// default LR and RR (sky blue, blue) were 26 apart.
constexpr double kDistinct = 30.0;

// ---- the replay of the default scenario, as `sinkwatch replay` runs it ----

struct Replayed {
  sg::TelemetryLog log;
  sg::ReplayConfig config;
  sg::ReplayResult result;
};

const Replayed& replayed(const std::string& source) {
  static std::map<std::string, Replayed> cache;
  auto it = cache.find(source);
  if (it == cache.end()) {
    Replayed r;
    r.log = sg::parse_telemetry_text(sg::embedded_scenario_text("embedding"), source);
    r.config.gravity_mps2 = sg::log_gravity(r.log);
    r.result = sg::run_replay(r.log, r.config);
    it = cache.emplace(source, std::move(r)).first;
  }
  return it->second;
}

std::string script_for(const std::string& source, const std::string& image = "/tmp/replay.png") {
  const Replayed& r = replayed(source);
  return sg::plot_script(r.log, r.config, r.result, image);
}

const Clause* titled(const Script& sc, const std::string& title) {
  for (const auto& plot : sc.plots) {
    for (const Clause& c : plot) {
      if (c.title == title) return &c;
    }
  }
  return nullptr;
}

std::string colour_of(const Script& sc, const Clause& c) {
  if (!c.linetype) return "(no lt)";
  const auto it = sc.colour.find(*c.linetype);
  return it == sc.colour.end() ? "(lt " + std::to_string(*c.linetype) + " undefined)" : it->second;
}

}  // namespace

TEST(PlotStyle, PaletteHasSixDistinctWheelColoursApartFromTheLevels) {
  const auto& wheels = sg::wheel_plot_styles();
  for (std::size_t i = 0; i < wheels.size(); ++i) {
    for (std::size_t j = i + 1; j < wheels.size(); ++j) {
      EXPECT_GE(delta_e(wheels[i].colour, wheels[j].colour), kDistinct) << wheels[i].name << " vs " << wheels[j].name;
    }
    for (const sg::PlotLineStyle& level : sg::level_plot_styles()) {
      EXPECT_GE(delta_e(wheels[i].colour, level.colour), kDistinct) << wheels[i].name << " vs " << level.name;
    }
  }
}

TEST(PlotStyle, EscapeGnuplotText) {
  EXPECT_EQ(sg::escape_gnuplot_text("x_y.csv"), "x\\_y.csv");
  EXPECT_EQ(sg::escape_gnuplot_text("a^b@c&d~e{f}g\\h"), "a\\^b\\@c\\&d\\~e\\{f\\}g\\\\h");
  EXPECT_EQ(sg::escape_gnuplot_text("it's\nhere"), "it''s here");
  EXPECT_EQ(sg::quote_gnuplot_string("/tmp/it's_x.png"), "/tmp/it''s_x.png");
  EXPECT_EQ(sg::quote_gnuplot_string("a\tb"), "a b");
}

TEST(ReplayPlot, SixDistinctWheelColoursNoneALevelColour) {
  const Script sc = read_script(script_for("<embedded embedding.csv>"));
  std::set<std::string> wheel_colours;
  std::vector<std::string> wheels;
  for (const char* w : sg::kWheelNames) {
    const Clause* current = titled(sc, std::string("|I| ") + w);
    const Clause* sinkage = titled(sc, std::string("z est ") + w);
    ASSERT_NE(current, nullptr) << w;
    ASSERT_NE(sinkage, nullptr) << w;
    EXPECT_EQ(colour_of(sc, *current), colour_of(sc, *sinkage)) << "wheel " << w << " has one colour in every panel";
    wheel_colours.insert(colour_of(sc, *current));
    wheels.push_back(colour_of(sc, *current));
  }
  EXPECT_EQ(wheel_colours.size(), 6U);
  for (std::size_t i = 0; i < wheels.size(); ++i) {
    for (std::size_t j = i + 1; j < wheels.size(); ++j) {
      if (wheels[i][0] != '#' || wheels[j][0] != '#') continue;
      EXPECT_GE(delta_e(wheels[i], wheels[j]), kDistinct) << sg::kWheelNames[i] << " vs " << sg::kWheelNames[j];
    }
  }
  // Every other line (levels, thresholds, the simulator's truth, decisions)
  // and the stop and embedding markers are in none of the wheel colours.
  std::size_t levels = 0;
  for (const auto& plot : sc.plots) {
    for (const Clause& c : plot) {
      if (c.title && (c.title->rfind("|I| ", 0) == 0 || c.title->rfind("z est ", 0) == 0)) continue;
      ++levels;
      EXPECT_EQ(wheel_colours.count(colour_of(sc, c)), 0U) << c.text;
      for (const std::string& w : wheels) {
        if (w[0] == '#' && colour_of(sc, c)[0] == '#') {
          EXPECT_GE(delta_e(w, colour_of(sc, c)), kDistinct) << c.text;
        }
      }
    }
  }
  EXPECT_GE(levels, 6U + 3U + 3U);  // I_max x 6; stop, caution, truth; state, stop, escape
  const std::regex marker_lt(R"(^set (?:arrow|label) .*\b(?:lt|tc lt) (\d+))");
  std::size_t markers = 0;
  for (const std::string& line : sc.lines) {
    std::smatch m;
    if (line.rfind("set arrow", 0) == 0 || line.rfind("set label", 0) == 0) {
      ASSERT_TRUE(std::regex_search(line, m, marker_lt)) << "a marker without a palette linetype: " << line;
      ++markers;
      const auto it = sc.colour.find(std::stoi(m[1]));
      ASSERT_NE(it, sc.colour.end()) << line;
      EXPECT_EQ(wheel_colours.count(it->second), 0U) << line;
    }
  }
  EXPECT_EQ(markers, 4U);  // the stop and the embedding: a line and a label each
}

TEST(ReplayPlot, EachLegendEntryHasTheColourOfItsLines) {
  const Script sc = read_script(script_for("<embedded embedding.csv>"));
  ASSERT_EQ(sc.plots.size(), 3U);
  const std::regex override_style(R"(\b(lc|linecolor|dt|dashtype|lw|linewidth)\b)");
  for (const auto& plot : sc.plots) {
    std::map<int, std::string> title_of_lt;
    std::set<std::string> titles;
    for (const Clause& c : plot) {
      // The look of a line is its linetype alone, so the legend key (drawn
      // from the same clause) cannot differ from it.
      ASSERT_TRUE(c.linetype.has_value()) << "no lt: " << c.text;
      EXPECT_TRUE(sc.colour.count(*c.linetype)) << "lt " << *c.linetype << " is not set: " << c.text;
      EXPECT_FALSE(std::regex_search(c.text, override_style)) << "style beyond lt: " << c.text;
      if (c.title) {
        EXPECT_TRUE(titles.insert(*c.title).second) << "titled twice: " << *c.title;
        title_of_lt.emplace(*c.linetype, *c.title);
      }
    }
    // An untitled line is drawn exactly like a titled one of the same plot:
    // that legend entry stands for it (I_max: one entry for six lines).
    for (const Clause& c : plot) {
      if (c.title) continue;
      EXPECT_TRUE(title_of_lt.count(*c.linetype)) << "a line with no legend entry of its look: " << c.text;
    }
  }
  // The I_max entry's colour is that of every I_max line (columns 8-13).
  const Clause* imax = titled(sc, "I_{max} (each wheel)");
  ASSERT_NE(imax, nullptr);
  std::size_t limit_lines = 0;
  for (const Clause& c : sc.plots.front()) {
    for (int col = 8; col <= 13; ++col) {
      if (c.text.find("u 1:" + std::to_string(col) + " ") != std::string::npos) {
        ++limit_lines;
        EXPECT_EQ(colour_of(sc, c), colour_of(sc, *imax)) << c.text;
      }
    }
  }
  EXPECT_EQ(limit_lines, 6U);
}

TEST(ReplayPlot, UnderscoreInTheFileNameIsEscapedInTheTitle) {
  const std::string source = "/data/run_2_log.csv";
  const std::string text = script_for(source, "/tmp/x_y.png");
  const Script sc = read_script(text);
  std::string title_line;
  for (const std::string& line : sc.lines) {
    if (line.rfind("set multiplot", 0) == 0) title_line = line;
  }
  ASSERT_FALSE(title_line.empty());
  EXPECT_NE(title_line.find("/data/run\\_2\\_log.csv"), std::string::npos) << title_line;
  EXPECT_EQ(title_line.find("run_2"), std::string::npos) << "an unescaped _ is a subscript: " << title_line;
  // The output name is a plain string: not escaped.
  EXPECT_NE(text.find("set output '/tmp/x_y.png'\n"), std::string::npos);
}

TEST(ReplayPlot, GnuplotDrawsTheEscapedTitleAsWritten) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot not installed";
  const fs::path dir = fs::temp_directory_path() / "sinkwatch_plot_style_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path image = dir / "x_y.svg";
  {
    std::ofstream(dir / "x_y.gp") << script_for("/data/run_2_log.csv", image.string());
  }
  ASSERT_EQ(std::system(("gnuplot '" + (dir / "x_y.gp").string() + "' 2>'" + (dir / "log").string() + "'").c_str()),
            0);
  std::ifstream in(image);
  std::stringstream svg;
  svg << in.rdbuf();
  // Enhanced text would split "run_2" into "run" and a subscript "2" (their
  // own <tspan>s); escaped, the name is one piece of text.
  EXPECT_NE(svg.str().find("/data/run_2_log.csv: sinkwatch flight code replay"), std::string::npos);
  // and I_{max} is still drawn with its subscript, i.e. enhanced text is on.
  EXPECT_EQ(svg.str().find("I_{max}"), std::string::npos);
  fs::remove_all(dir);
}

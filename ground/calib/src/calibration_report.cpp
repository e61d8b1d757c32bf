// calibration_report.cpp: text and JSON output of a calibration.
#include "sinkwatch/ground/strf.hpp"
#include "sinkwatch/ground/calibration_report.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <ostream>
#include <sstream>

namespace sinkwatch {
namespace ground {

namespace {

constexpr std::array<const char*, kCoefficientCount> kNames = {"C1", "C2", "C3"};
constexpr std::array<const char*, kCoefficientCount> kKeys = {"c1", "c2", "c3"};

// A number for the table, or "-" when it does not exist.
std::string num(double value, const char* fmt = "%.4f") {
  return std::isfinite(value) ? strf(fmt, value) : std::string("-");
}

std::string describe_fixed(const FixedCoefficients& fixed) {
  std::string text;
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    if (fixed.value[k]) {
      text += text.empty() ? "" : ", ";
      text += std::string(kKeys[k]) + "=" + strf("%g", *fixed.value[k]);
    }
  }
  return text;
}

// The solver line and the coefficient table: estimate, standard error and
// 95 % interval of each free coefficient.
void print_coefficients(std::ostream& out, const CalibrationFit& fit) {
  if (fit.free_count > 0) {
    out << strf("  least squares by SVD of A: %zu rows, %zu free, %zu degrees of freedom, "
                  "t(0.975) = %.3f\n\n",
                  fit.rows, fit.free_count, fit.dof, fit.t_quantile);
  } else {
    out << strf("  all coefficients fixed: %zu rows evaluated, nothing fitted\n\n", fit.rows);
  }
  out << "  coef    estimate     std err    95 % interval\n";
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    if (fit.free[k]) {
      out << strf("  %-4s %11.6f %11.6f    [%9.5f, %9.5f]\n", kNames[k], fit.c[k],
                    fit.std_err[k], fit.ci_low[k], fit.ci_high[k]);
    } else {
      out << strf("  %-4s %11.6f       fixed\n", kNames[k], fit.c[k]);
    }
  }
}

// One row of the correlation matrix, over the free coefficients only.
void print_correlation_row(std::ostream& out, const CalibrationFit& fit, std::size_t k) {
  out << strf("  %-11s", kNames[k]);
  for (std::size_t q = 0; q < kCoefficientCount; ++q) {
    if (fit.free[q]) {
      out << strf("%8.4f", fit.correlation[k][q]);
    }
  }
  out << '\n';
}

// The correlation matrix of the free coefficients (only when two or more
// are free: one has nothing to correlate with).
void print_correlation(std::ostream& out, const CalibrationFit& fit) {
  if (fit.free_count <= 1) {
    return;
  }
  out << "\n  correlation ";
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    if (fit.free[k]) {
      out << strf("%8s", kNames[k]);
    }
  }
  out << '\n';
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    if (fit.free[k]) {
      print_correlation_row(out, fit, k);
    }
  }
}

// Conditioning, residual RMS, leave-one-out RMS and the normal-equations
// cross-check of the SVD solution.
void print_quality(std::ostream& out, const CalibrationFit& fit) {
  if (fit.free_count > 0) {
    out << strf("  condition number of A   %.4g   (columns scaled to unit length: %.4g)\n",
                  fit.condition_number, fit.condition_number_scaled);
  }
  out << strf("  residual RMS            %.4g", fit.rms);
  if (fit.free_count > 0) {
    out << strf("   (residual std, n - p: %.4g)", fit.residual_std);
  }
  out << '\n';
  out << "  leave-one-out RMS       " << num(fit.loo_rms, "%.4g") << '\n';
  if (fit.free_count > 0) {
    out << "  normal equations        C =";
    for (std::size_t k = 0; k < kCoefficientCount; ++k) {
      out << ' ' << num(fit.normal_equations_c[k], "%.6f");
    }
    out << strf("   (max |difference| from SVD: %.2g)\n", fit.normal_equations_max_diff);
  }
}

void print_fit(std::ostream& out, const CalibrationFit& fit) {
  print_coefficients(out, fit);
  print_correlation(out, fit);
  out << '\n';
  print_quality(out, fit);
  out << "\n  residuals by slip\n";
  out << "      slip      DP/W    fitted  residual  LOO res.   line\n";
  for (const Residual& r : fit.residuals) {
    out << strf("  %8.4f %9.4f %9.4f %9.4f ", r.slip, r.measured, r.fitted, r.residual)
        << strf("%9s", num(r.loo_residual).c_str()) << strf(" %6zu\n", r.line);
  }
}

// JSON helpers: a non-finite number has no JSON spelling and becomes null.
std::string json_number(double value) {
  return std::isfinite(value) ? strf("%.17g", value) : std::string("null");
}

std::string json_string(const std::string& text) {
  std::string quoted = "\"";
  for (char ch : text) {
    switch (ch) {
      case '"':
        quoted += "\\\"";
        break;
      case '\\':
        quoted += "\\\\";
        break;
      case '\n':
        quoted += "\\n";
        break;
      case '\t':
        quoted += "\\t";
        break;
      case '\r':
        quoted += "\\r";
        break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20) {
          quoted += strf("\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(ch)));
        } else {
          quoted += ch;
        }
    }
  }
  return quoted + "\"";
}

std::string json_per_coefficient(const Coefficients& values) {
  std::string text = "{";
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    text += strf("\"%s\": ", kKeys[k]) + json_number(values[k]);
    text += k + 1 < kCoefficientCount ? ", " : "}";
  }
  return text;
}

// The members of one fit, without braces, each line indented by `pad`.
std::string json_fit_members(const CalibrationFit& fit, const std::string& pad) {
  std::ostringstream out;
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    out << pad << '"' << kKeys[k] << "\": " << json_number(fit.c[k]) << ",\n";
  }
  out << pad << "\"free\": {";
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    out << '"' << kKeys[k] << "\": " << (fit.free[k] ? "true" : "false")
        << (k + 1 < kCoefficientCount ? ", " : "},\n");
  }
  out << pad << "\"std_err\": " << json_per_coefficient(fit.std_err) << ",\n";
  out << pad << "\"ci95\": {";
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    out << '"' << kKeys[k] << "\": [" << json_number(fit.ci_low[k]) << ", "
        << json_number(fit.ci_high[k]) << ']' << (k + 1 < kCoefficientCount ? ", " : "},\n");
  }
  out << pad << "\"correlation\": [";
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    out << '[';
    for (std::size_t q = 0; q < kCoefficientCount; ++q) {
      out << json_number(fit.correlation[k][q]) << (q + 1 < kCoefficientCount ? ", " : "]");
    }
    out << (k + 1 < kCoefficientCount ? ", " : "],\n");
  }
  out << pad << "\"condition_number\": " << json_number(fit.condition_number) << ",\n";
  out << pad << "\"condition_number_scaled\": " << json_number(fit.condition_number_scaled)
      << ",\n";
  out << pad << "\"rms\": " << json_number(fit.rms) << ",\n";
  out << pad << "\"residual_std\": " << json_number(fit.residual_std) << ",\n";
  out << pad << "\"loo_rms\": " << json_number(fit.loo_rms) << ",\n";
  out << pad << "\"rows\": " << fit.rows << ",\n";
  out << pad << "\"dof\": " << fit.dof << ",\n";
  out << pad << "\"t_quantile_975\": " << json_number(fit.t_quantile) << ",\n";
  out << pad << "\"normal_equations\": {\"c\": " << json_per_coefficient(fit.normal_equations_c)
      << ", \"max_abs_diff_from_svd\": " << json_number(fit.normal_equations_max_diff) << "},\n";
  out << pad << "\"residuals\": [";
  for (std::size_t i = 0; i < fit.residuals.size(); ++i) {
    const Residual& r = fit.residuals[i];
    out << (i == 0 ? "\n" : ",\n") << pad << "  {\"line\": " << r.line
        << ", \"slip\": " << json_number(r.slip) << ", \"measured\": " << json_number(r.measured)
        << ", \"fitted\": " << json_number(r.fitted) << ", \"residual\": "
        << json_number(r.residual) << ", \"loo_residual\": " << json_number(r.loo_residual)
        << '}';
  }
  out << '\n' << pad << ']';
  return out.str();
}

void print_flight_table(std::ostream& out, const FlightTableSummary& t) {
  out << strf("\n  flight parameter table %s: %zu bytes, CRC-32 0x%08x, table version %u\n",
                t.path.c_str(), t.bytes, static_cast<unsigned>(t.crc),
                static_cast<unsigned>(t.table_version));
  out << "  other sections from the " << t.base << "; wheel radius " << strf("%.6g", t.wheel_radius_m)
      << " m " << (t.radius_from_data ? "from the data (or --radius)" : "kept from the base table") << '\n';
  out << "  as the flight code reads it (Q7.24 coefficients, Q15.16 loads):\n";
  out << "    load_N          C1          C2          C3   DP_max/W\n";
  for (const FlightTableSummary::Row& r : t.rows) {
    out << strf("  %8.3f  %10.7f  %10.7f  %10.7f  %9.6f\n", r.load_n, r.c1, r.c2, r.c3,
                  r.dp_max_ratio);
  }
}

// The C(W) table of --per-load: one fit per load, a row each.
void print_load_table(std::ostream& out, const std::vector<LoadFit>& load_table) {
  out << "\n  C(W) table, one fit per load\n";
  out << "    load_N  rows        C1 +- se            C2 +- se            C3 +- se"
         "              RMS   LOO RMS      cond\n";
  for (const LoadFit& entry : load_table) {
    const CalibrationFit& f = entry.fit;
    out << strf("  %8.3f %5zu", entry.load_n, f.rows);
    for (std::size_t k = 0; k < kCoefficientCount; ++k) {
      if (f.free[k]) {
        out << strf("  %8.4f +- %-7.2g", f.c[k], f.std_err[k]);
      } else {
        out << strf("  %8.4f (fixed)   ", f.c[k]);
      }
    }
    out << strf("  %9.4g %9s  %8s\n", f.rms, num(f.loo_rms, "%.4g").c_str(),
                  num(f.condition_number, "%.3g").c_str());
  }
}

}  // namespace

void print_report(std::ostream& out, const CalibrationReport& report) {
  out << "sinkwatch calibrate: " << report.source << '\n';
  out << "  " << report.fit.rows << " rows, " << to_string(report.form)
      << " input; model DP/W = C1*T/(rW) - C2*z/r - C3 (Eq. 11)";
  const std::string fixed = describe_fixed(report.fixed);
  if (!fixed.empty()) {
    out << "; fixed " << fixed;
  }
  out << '\n';
  if (report.per_load) {
    out << "  all loads pooled:\n";
  }
  print_fit(out, report.fit);
  if (report.per_load) {
    print_load_table(out, report.load_table);
  }
  if (report.flight_table) {
    print_flight_table(out, *report.flight_table);
  }
}

std::string to_json(const CalibrationReport& report) {
  std::ostringstream out;
  out << "{\n";
  out << "  \"source\": " << json_string(report.source) << ",\n";
  out << "  \"form\": " << json_string(to_string(report.form)) << ",\n";
  out << "  \"model\": \"DP/W = C1*T/(rW) - C2*z/r - C3\",\n";
  out << "  \"solver\": \"SVD least squares\",\n";
  out << "  \"fixed\": {";
  bool first = true;
  for (std::size_t k = 0; k < kCoefficientCount; ++k) {
    if (report.fixed.value[k]) {
      out << (first ? "" : ", ") << '"' << kKeys[k] << "\": " << json_number(*report.fixed.value[k]);
      first = false;
    }
  }
  out << "},\n";
  out << json_fit_members(report.fit, "  ");
  if (report.per_load) {
    out << ",\n  \"per_load\": [";
    for (std::size_t i = 0; i < report.load_table.size(); ++i) {
      out << (i == 0 ? "\n" : ",\n") << "    {\n      \"load_N\": "
          << json_number(report.load_table[i].load_n) << ",\n"
          << json_fit_members(report.load_table[i].fit, "      ") << "\n    }";
    }
    out << "\n  ]";
  }
  if (report.flight_table) {
    const FlightTableSummary& t = *report.flight_table;
    out << ",\n  \"flight_table\": {\"path\": " << json_string(t.path) << ", \"bytes\": " << t.bytes
        << ", \"crc32\": " << t.crc << ", \"table_version\": " << t.table_version
        << ", \"wheel_radius_m\": " << json_number(t.wheel_radius_m)
        << ", \"radius_from_data\": " << (t.radius_from_data ? "true" : "false")
        << ", \"base\": " << json_string(t.base) << ", \"rows\": [";
    for (std::size_t i = 0; i < t.rows.size(); ++i) {
      const FlightTableSummary::Row& r = t.rows[i];
      out << (i == 0 ? "" : ", ") << "{\"load_N\": " << json_number(r.load_n)
          << ", \"c1\": " << json_number(r.c1) << ", \"c2\": " << json_number(r.c2)
          << ", \"c3\": " << json_number(r.c3) << ", \"dp_max_ratio\": " << json_number(r.dp_max_ratio)
          << '}';
    }
    out << "]}";
  }
  out << "\n}\n";
  return out.str();
}

}  // namespace ground
}  // namespace sinkwatch

// diagnosis_report.cpp: JSON, Markdown summary and gnuplot plots.
#include "sinkwatch/ground/diagnosis_report.hpp"

#include "sinkwatch/ground/output_file.hpp"
#include "sinkwatch/ground/plot_style.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace sinkwatch {
namespace ground {

namespace {

std::string num(double v) {
  if (!std::isfinite(v)) {
    return "null";
  }
  std::ostringstream os;
  os << std::setprecision(10) << v;
  return os.str();
}

std::string quote(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    switch (ch) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(ch)));
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

std::string per_channel(const std::vector<ChannelInfo>& channels, const std::vector<double>& values) {
  std::string out = "{";
  for (std::size_t c = 0; c < channels.size() && c < values.size(); ++c) {
    out += (c > 0 ? ", " : "") + quote(channels[c].name) + ": " + num(values[c]);
  }
  return out + "}";
}

std::string fit_json(const DiagnosisResult& r, const FitResult& fit, const std::string& indent) {
  std::ostringstream os;
  os << "{\n" << indent << "  \"label\": " << quote(fit.label) << ",\n" << indent << "  \"parameters\": {";
  for (std::size_t i = 0; i < fit.names.size(); ++i) {
    os << (i > 0 ? ", " : "") << quote(fit.names[i]) << ": " << num(fit.values[i]);
  }
  os << "},\n"
     << indent << "  \"converged\": " << (fit.converged ? "true" : "false") << ",\n"
     << indent << "  \"solver_message\": " << quote(fit.solver_message) << ",\n"
     << indent << "  \"iterations\": " << fit.iterations << ",\n"
     << indent << "  \"train_rows\": " << fit.train_rows << ",\n"
     << indent << "  \"train_chi2\": " << num(fit.train_chi2) << ",\n"
     << indent << "  \"aic\": " << num(fit.aic) << ",\n"
     << indent << "  \"bic\": " << num(fit.bic) << ",\n"
     << indent << "  \"train_rms\": " << per_channel(r.channels, fit.train_rms) << ",\n"
     << indent << "  \"heldout_rms\": " << per_channel(r.channels, fit.heldout_rms) << ",\n"
     << indent << "  \"train_rms_noise_units\": " << num(fit.train_rms_scaled) << ",\n"
     << indent << "  \"heldout_rms_noise_units\": " << num(fit.heldout_rms_scaled) << ",\n"
     << indent << "  \"heldout_failures\": " << fit.heldout_failures << "\n"
     << indent << "}";
  return os.str();
}

// The noise residual (i, c) is divided by: the row's, else the channel's
// (a result built without row noise), else NaN (no noise: not_enough_data).
double row_noise_of(const DiagnosisResult& r, std::size_t i, std::size_t c) {
  if (i < r.row_noise.size()) {
    return r.row_noise[i][c];
  }
  return c < r.noise.size() ? r.noise[c].sigma : std::nan("");
}

const RankedEffect* top_effect(const DiagnosisResult& r) {
  if (r.ranking.empty() || !r.ranking.front().identifiable) {
    return nullptr;
  }
  return &r.ranking.front();
}

// The settings of the run, as (name, value) text pairs: the caller's (model
// inputs), the wheel, the split and noise rules, thresholds and starts.
std::vector<NamedSetting> settings_used(const DiagnosisResult& r) {
  std::vector<NamedSetting> out = r.settings.inputs;
  std::ostringstream radius;
  std::ostringstream width;
  std::vector<double> radii;
  std::vector<double> widths;
  for (const DiagnosisRow& row : r.rows) {
    if (std::find(radii.begin(), radii.end(), row.radius_m) == radii.end()) {
      radii.push_back(row.radius_m);
      radius << (radii.size() > 1 ? ", " : "") << row.radius_m;
    }
    if (std::find(widths.begin(), widths.end(), row.width_m) == widths.end()) {
      widths.push_back(row.width_m);
      width << (widths.size() > 1 ? ", " : "") << row.width_m;
    }
  }
  const DiagnosisSettings& s = r.settings;
  std::ostringstream starts;
  for (std::size_t i = 0; i < s.start_multiples.size(); ++i) {
    starts << (i > 0 ? ", " : "") << s.start_multiples[i];
  }
  auto text = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  out.push_back({"wheel radius (m)", radius.str()});
  out.push_back({"wheel width (m)", width.str()});
  out.push_back({"split", r.split_rule});
  out.push_back({"cross-validation", r.cv_rule});
  out.push_back({"gap threshold (x noise)", text(s.gap_threshold)});
  out.push_back({"residual threshold (x noise)", text(s.residual_threshold)});
  out.push_back({"residual bound (x noise): z of the noise's F quantile, best family's mean held-out leverage -> bound",
                 text(s.residual_z) + ", " + text(r.heldout_leverage) + " -> " + text(r.residual_bound)});
  out.push_back({"explain threshold (% shrink)", text(s.explain_threshold_pct)});
  out.push_back({"partial threshold (% shrink)", text(s.partial_threshold_pct)});
  out.push_back({"tie (fraction of the base's held-out RMS)", text(s.tie_fraction)});
  out.push_back({"candidate starts (x initial size)", starts.str()});
  out.push_back({"minimum rows", std::to_string(s.min_rows)});
  out.push_back({"solver", "Ceres, forward differences, max " + std::to_string(s.max_iterations) +
                               " iterations, function tolerance " + text(s.function_tolerance) +
                               ", parameter tolerance " + text(s.parameter_tolerance)});
  if (r.two_condition) {
    out.push_back({"base condition", r.base_source + " (" + std::to_string(r.base_rows) +
                                         " rows; base parameters fitted there and held fixed)"});
  }
  return out;
}

std::string settings_json(const DiagnosisResult& r) {
  std::string out = "{";
  const std::vector<NamedSetting> settings = settings_used(r);
  for (std::size_t i = 0; i < settings.size(); ++i) {
    out += (i > 0 ? ", " : "") + quote(settings[i].name) + ": " + quote(settings[i].value);
  }
  return out + "}";
}

std::string noise_json(const DiagnosisResult& r) {
  std::ostringstream os;
  os << "[";
  for (std::size_t c = 0; c < r.noise.size(); ++c) {
    os << (c > 0 ? ", " : "") << "{\"channel\": " << quote(r.noise[c].channel) << ", \"sigma\": " << num(r.noise[c].sigma)
       << ", \"method\": " << quote(r.noise[c].method) << ", \"dof\": " << r.noise[c].dof
       << ", \"floor\": " << num(r.noise[c].floor) << ", \"relative\": " << num(r.noise[c].relative) << "}";
  }
  os << "]";
  return os.str();
}

std::string where_json(const DiagnosisResult& r) {
  std::ostringstream os;
  os << "{\n    \"largest\": " << quote(r.where.largest) << ",\n    \"channels\": [";
  for (std::size_t c = 0; c < r.where.channels.size(); ++c) {
    const ChannelGap& g = r.where.channels[c];
    os << (c > 0 ? "," : "") << "\n      {\"channel\": " << quote(g.channel) << ", \"unit\": " << quote(g.unit)
       << ", \"noise_sigma\": " << num(g.noise_sigma) << ", \"noise_method\": " << quote(g.noise_method)
       << ", \"train_rms\": " << num(g.train_rms) << ", \"heldout_rms\": " << num(g.heldout_rms)
       << ", \"heldout_bias\": " << num(g.heldout_bias) << ", \"train_over_noise\": " << num(g.train_over_noise)
       << ", \"heldout_over_noise\": " << num(g.heldout_over_noise) << "}";
  }
  os << "\n    ],\n    \"regimes\": [";
  for (std::size_t b = 0; b < r.where.bins.size(); ++b) {
    const RegimeBin& bin = r.where.bins[b];
    os << (b > 0 ? "," : "") << "\n      {\"regime\": " << quote(bin.regime) << ", \"label\": " << quote(bin.label)
       << ", \"low\": " << num(bin.low) << ", \"high\": " << num(bin.high) << ", \"rows\": " << bin.rows
       << ", \"heldout_rows\": " << bin.heldout_rows << ", \"rms\": " << per_channel(r.channels, bin.rms)
       << ", \"mean\": " << per_channel(r.channels, bin.mean)
       << ", \"rms_over_noise\": " << per_channel(r.channels, bin.rms_over_noise) << "}";
  }
  os << "\n    ],\n    \"components\": [";
  for (std::size_t k = 0; k < r.where.components.size(); ++k) {
    const GapComponent& g = r.where.components[k];
    os << (k > 0 ? "," : "") << "\n      {\"name\": " << quote(g.name) << ", \"channel\": " << quote(g.channel)
       << ", \"rms\": " << num(g.rms) << ", \"max_abs\": " << num(g.max_abs) << ", \"over_noise\": " << num(g.over_noise)
       << ", \"note\": " << quote(g.note) << "}";
  }
  os << "\n    ]\n  }";
  return os.str();
}

std::string effect_json(const DiagnosisResult& r, const RankedEffect& e, std::size_t rank) {
  std::ostringstream os;
  os << "{\"rank\": " << rank << ", \"effect\": " << quote(e.effect) << ", \"family\": " << quote(e.family)
     << ", \"form\": " << quote(e.form) << ", \"description\": " << quote(e.description)
     << ", \"identifiable\": " << (e.identifiable ? "true" : "false") << ", \"note\": " << quote(e.note)
     << ",\n     \"heldout_rms_before\": " << num(e.heldout_rms_before)
     << ", \"heldout_rms_after\": " << num(e.heldout_rms_after) << ", \"shrink_pct\": " << num(e.shrink_pct)
     << ", \"rms_unit\": \"noise-scaled, combined over channels\",\n     \"channels\": {";
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    os << (c > 0 ? ", " : "") << quote(r.channels[c].name) << ": {\"heldout_rms_before\": " << num(e.channel_before[c])
       << ", \"heldout_rms_after\": " << num(e.channel_after[c]) << ", \"shrink_pct\": " << num(e.channel_shrink_pct[c])
       << ", \"unit\": " << quote(r.channels[c].unit) << "}";
  }
  os << "},\n     \"fitted\": {";
  std::size_t i = 0;
  for (const auto& [name, value] : e.fitted) {
    os << (i++ > 0 ? ", " : "") << quote(name) << ": " << num(value);
  }
  os << "}, \"nominal_size\": " << num(e.nominal_size) << ", \"train_bic\": " << num(e.train_bic)
     << ", \"delta_bic\": " << num(e.delta_bic) << ",\n     \"fit\": "
     << (e.identifiable ? fit_json(r, e.fit, "     ") : std::string("null")) << "}";
  return os.str();
}

std::string families_json(const DiagnosisResult& r) {
  std::ostringstream os;
  os << "[";
  for (std::size_t k = 0; k < r.families.size(); ++k) {
    const RankedFamily& f = r.families[k];
    os << (k > 0 ? "," : "") << "\n    {\"rank\": " << k + 1 << ", \"family\": " << quote(f.family)
       << ", \"best_form\": " << quote(f.best_form) << ", \"best_effect\": " << quote(f.best_effect)
       << ", \"identifiable\": " << (f.identifiable ? "true" : "false")
       << ", \"heldout_rms_after\": " << num(f.heldout_rms_after) << ", \"shrink_pct\": " << num(f.shrink_pct)
       << ", \"delta_bic\": " << num(f.delta_bic) << ", \"forms\": [";
    for (std::size_t i = 0; i < f.forms.size(); ++i) {
      const FormScore& s = f.forms[i];
      os << (i > 0 ? ", " : "") << "{\"form\": " << quote(s.form) << ", \"effect\": " << quote(s.effect)
         << ", \"identifiable\": " << (s.identifiable ? "true" : "false")
         << ", \"heldout_rms_after\": " << num(s.heldout_rms_after) << ", \"shrink_pct\": " << num(s.shrink_pct) << "}";
    }
    os << "]}";
  }
  os << "\n  ]";
  return os.str();
}

std::string effects_json(const DiagnosisResult& r, const std::vector<RankedEffect>& effects) {
  std::string out = "[";
  for (std::size_t k = 0; k < effects.size(); ++k) {
    out += (k > 0 ? ",\n    " : "\n    ") + effect_json(r, effects[k], k + 1);
  }
  return out + "\n  ]";
}

}  // namespace

std::string to_json(const DiagnosisResult& r) {
  std::ostringstream os;
  os << "{\n  \"model\": " << quote(r.model) << ",\n  \"source\": " << quote(r.source) << ",\n"
     << "  \"rows\": " << r.rows.size() << ",\n  \"train_rows\": " << r.train.size()
     << ",\n  \"heldout_rows\": " << r.heldout.size() << ",\n  \"split_rule\": " << quote(r.split_rule) << ",\n"
     << "  \"cv_folds\": " << r.folds.size() << ",\n  \"cv_rule\": " << quote(r.cv_rule) << ",\n"
     << "  \"cv_heldout_rms\": " << per_channel(r.channels, r.cv_heldout_rms) << ",\n"
     << "  \"cv_heldout_rms_noise_units\": " << num(r.cv_heldout_rms_scaled) << ",\n"
     << "  \"heldout_leverage\": " << num(r.heldout_leverage) << ",\n"
     << "  \"residual_bound_noise_units\": " << num(r.residual_bound) << ",\n"
     << "  \"verdict\": " << quote(verdict_name(r.verdict)) << ",\n  \"verdict_text\": " << quote(r.verdict_text)
     << ",\n  \"settings\": " << settings_json(r) << ",\n  \"noise\": " << noise_json(r) << ",\n";
  if (r.verdict != Verdict::not_enough_data) {
    os << "  \"base_fit\": " << fit_json(r, r.base, "  ") << ",\n  \"where\": " << where_json(r) << ",\n";
  }
  os << "  \"two_condition\": " << (r.two_condition ? "true" : "false");
  if (r.two_condition) {
    os << ",\n  \"base_data\": " << quote(r.base_source) << ",\n  \"base_data_rows\": " << r.base_rows;
    if (r.verdict != Verdict::not_enough_data) {
      os << ",\n  \"base_condition_fit\": " << fit_json(r, r.base_condition_fit, "  ");
    }
    os << ",\n  \"references\": " << effects_json(r, r.references);
  }
  os << ",\n  \"families\": " << families_json(r) << ",\n  \"ranking\": " << effects_json(r, r.ranking)
     << ",\n  \"notes\": [";
  for (std::size_t k = 0; k < r.notes.size(); ++k) {
    os << (k > 0 ? ", " : "") << quote(r.notes[k]);
  }
  os << "]\n}\n";
  return os.str();
}

namespace {

void markdown_settings(std::ostream& os, const DiagnosisResult& r) {
  os << "## Settings\n\n| setting | value |\n|---|---|\n";
  for (const NamedSetting& s : settings_used(r)) {
    os << "| " << s.name << " | " << s.value << " |\n";
  }
  os << "\n";
}

void markdown_noise_and_base(std::ostream& os, const DiagnosisResult& r) {
  os << "## Noise per channel\n\nA row's noise is hypot(floor, relative x |value|); sigma is its RMS over the rows.\n\n"
     << "| channel | sigma | floor | relative | method | dof |\n|---|---|---|---|---|---|\n";
  for (const ChannelNoiseEstimate& n : r.noise) {
    os << "| " << n.channel << " | " << n.sigma << " | " << n.floor << " | " << n.relative << " | " << n.method << " | "
       << n.dof << " |\n";
  }
  if (r.two_condition) {
    os << "\n## Base condition\n\nBase parameters fitted on all " << r.base_rows << " rows of " << r.base_source
       << " and held fixed on this data: ";
    for (std::size_t i = 0; i < r.base_condition_fit.names.size(); ++i) {
      os << (i > 0 ? ", " : "") << r.base_condition_fit.names[i] << " = " << r.base_condition_fit.values[i];
    }
    os << " (" << (r.base_condition_fit.converged ? "converged" : "NOT converged") << ", training RMS "
       << r.base_condition_fit.train_rms_scaled << "x noise of the base condition)\n";
  }
  os << "\n## Base fit\n\n";
  for (std::size_t i = 0; i < r.base.names.size(); ++i) {
    os << (i > 0 ? ", " : "") << r.base.names[i] << " = " << r.base.values[i];
  }
  os << "\n\n(" << (r.base.converged ? "converged" : "NOT converged") << ", " << r.base.iterations << " iterations"
     << (r.two_condition ? "; held fixed from the base condition" : "") << ")\n\n";
}

void markdown_where(std::ostream& os, const DiagnosisResult& r) {
  os << "## Where\n\n" << r.where.largest << "\n\n"
     << "| channel | unit | noise | train RMS | held-out RMS | held-out bias | train/noise | held-out/noise |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const ChannelGap& g : r.where.channels) {
    os << "| " << g.channel << " | " << g.unit << " | " << g.noise_sigma << " | " << g.train_rms << " | "
       << g.heldout_rms << " | " << g.heldout_bias << " | " << g.train_over_noise << " | " << g.heldout_over_noise
       << " |\n";
  }
  os << "\nResiduals of the base fit (all rows) by regime, RMS / noise per channel:\n\n| regime | bin | rows (held out) |";
  for (const ChannelInfo& c : r.channels) {
    os << " " << c.name << " |";
  }
  os << "\n|---|---|---|";
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    os << "---|";
  }
  os << "\n";
  for (const RegimeBin& bin : r.where.bins) {
    os << "| " << bin.regime << " | " << bin.label << " | " << bin.rows << " (" << bin.heldout_rows << ") |";
    for (std::size_t c = 0; c < r.channels.size(); ++c) {
      os << " " << bin.rms_over_noise[c] << " (bias " << bin.mean[c] << ") |";
    }
    os << "\n";
  }
  if (!r.where.components.empty()) {
    os << "\nOther components of the gap:\n\n| component | channel | RMS | max | RMS / noise | note |\n|---|---|---|---|---|---|\n";
    for (const GapComponent& g : r.where.components) {
      os << "| " << g.name << " | " << g.channel << " | " << g.rms << " | " << g.max_abs << " | " << g.over_noise
         << " | " << g.note << " |\n";
    }
  }
}

void markdown_families(std::ostream& os, const DiagnosisResult& r) {
  os << "\n## Which family\n\nEach family scored by its best form (lowest pooled held-out RMS, noise units).\n\n"
     << "| rank | family | best form | after | shrink % | delta BIC | other forms: after (shrink %) |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < r.families.size(); ++k) {
    const RankedFamily& f = r.families[k];
    os << "| " << k + 1 << " | " << f.family << " | " << (f.best_form.empty() ? "-" : f.best_form) << " | "
       << f.heldout_rms_after << " | " << f.shrink_pct << " | " << f.delta_bic << " | ";
    for (std::size_t i = 1; i < f.forms.size(); ++i) {
      os << f.forms[i].form << ": " << f.forms[i].heldout_rms_after << " (" << f.forms[i].shrink_pct << ") ";
    }
    os << "|\n";
  }
}

void markdown_effect_row(std::ostream& os, const DiagnosisResult& r, const RankedEffect& e, const std::string& rank) {
  os << "| " << rank << " | " << e.effect << " | " << e.heldout_rms_before << " | " << e.heldout_rms_after << " | "
     << e.shrink_pct << " | " << e.delta_bic << " | ";
  for (const auto& [name, value] : e.fitted) {
    os << name << " = " << value << " ";
  }
  if (!e.note.empty()) {
    os << "(" << e.note << ")";
  }
  os << " | ";
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    os << r.channels[c].name << " " << e.channel_before[c] << " -> " << e.channel_after[c] << " "
       << r.channels[c].unit << " (" << e.channel_shrink_pct[c] << " %); ";
  }
  os << "|\n";
}

void markdown_ranking(std::ostream& os, const DiagnosisResult& r) {
  os << "\n## Which effect, and how far it shrinks the held-out gap\n\n"
     << "Held-out RMS in noise units, combined over channels, " << r.cv_rule
     << "; ranked by held-out RMS after, near-ties by training BIC. Fitted sizes are those of the first split.\n\n"
     << "| rank | effect | before | after | shrink % | delta BIC | fitted | per channel: before -> after unit (shrink %) |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < r.ranking.size(); ++k) {
    markdown_effect_row(os, r, r.ranking[k], std::to_string(k + 1));
  }
  for (const RankedEffect& e : r.references) {
    markdown_effect_row(os, r, e, "reference");
  }
  if (!r.references.empty()) {
    os << "\nreference: not a candidate effect but the base parameters refitted on this data (a soil change).\n";
  }
}

}  // namespace

std::string summary_markdown(const DiagnosisResult& r) {
  std::ostringstream os;
  os << std::setprecision(4);
  os << "# Sim-to-real gap diagnosis\n\n"
     << "- data: " << r.source << " (" << r.rows.size() << " rows)\n"
     << "- model: " << r.model << "\n";
  if (r.two_condition) {
    os << "- base condition: " << r.base_source << " (" << r.base_rows << " rows)\n";
  }
  os << "- split: " << r.split_rule << "\n"
     << "- ranking scored on: " << r.cv_rule << "\n"
     << "- verdict: **" << verdict_name(r.verdict) << "**: " << r.verdict_text << "\n\n";
  markdown_settings(os, r);
  if (r.verdict != Verdict::not_enough_data) {
    markdown_noise_and_base(os, r);
    markdown_where(os, r);
    markdown_families(os, r);
    markdown_ranking(os, r);
  }
  for (const std::string& note : r.notes) {
    os << "\nNote: " << note << "\n";
  }
  return os.str();
}

namespace {

// The largest finite |residual / row noise| of a fit (0 for none).
double largest_scaled(const DiagnosisResult& r, const FitResult* fit) {
  double largest = 0.0;
  if (fit == nullptr) {
    return largest;
  }
  for (std::size_t i = 0; i < r.rows.size() && i < fit->residuals.size(); ++i) {
    for (std::size_t c = 0; c < r.channels.size() && c < fit->residuals[i].size(); ++c) {
      // As in residuals.dat: the residual over the row's noise in that channel.
      const double v = fit->residuals[i][c] / row_noise_of(r, i, c);
      if (std::isfinite(v)) {
        largest = std::max(largest, std::fabs(v));
      }
    }
  }
  return largest;
}

}  // namespace

ResidualRange residual_plot_range(const DiagnosisResult& r) {
  const RankedEffect* top = top_effect(r);
  const double largest = std::max(largest_scaled(r, &r.base), largest_scaled(r, top != nullptr ? &top->fit : nullptr));
  // Symmetric about zero with a margin, so that the zero line is in the middle
  // of every panel; at least +-1 noise unit.
  const double half = std::max(1.0, largest * 1.05);
  return {-half, half};
}

std::string residuals_plot_script(const DiagnosisResult& r) {
  const RankedEffect* top = top_effect(r);
  const std::string top_name = top != nullptr ? top->effect : std::string("none");
  const ResidualRange range = residual_plot_range(r);
  std::ostringstream gp;
  gp << "# gnuplot script written by sinkwatch diagnose; run: gnuplot residuals.gp\n"
     << "set terminal svg size 1200," << 360 * r.channels.size() << " dynamic font 'sans,11'\n"
     << "set termoption noenhanced\n"  // names like traction_coeff are not subscripts
     << gnuplot_linetypes() << "set datafile missing 'NaN'\n"
     << "set key outside right top\nset grid\nset xzeroaxis lt -1\n"
     // One y-range for every panel, so that base and base + effect, and the
     // channels (all in noise units), can be compared by eye.
     << "set yrange [" << num(range.low) << ":" << num(range.high) << "]\n";
  const std::size_t nch = r.channels.size();
  const int train_lt = sample_linetype(PlotSample::training);
  const int held_lt = sample_linetype(PlotSample::held_out);
  for (const std::string& axis : {std::string("slip"), std::string("load")}) {
    const int xcol = axis == "slip" ? 1 : 2;
    gp << "set output 'residuals_vs_" << axis << ".svg'\n"
       << "set multiplot layout " << nch << ",2 title 'residual / noise against " << axis
       << " (open: training, filled: held out)'\n";
    for (std::size_t c = 0; c < nch; ++c) {
      for (int which = 0; which < 2; ++which) {
        const std::size_t col = 5 + c + (which == 1 ? nch : 0);
        gp << "set title '"
           << quote_gnuplot_string(r.channels[c].name + ": " + (which == 0 ? std::string("base") : "base + " + top_name))
           << "'\nset xlabel '" << (axis == "slip" ? "slip" : "load (N)") << "'\nset ylabel 'residual / noise'\n"
           << "plot 'residuals.dat' using " << xcol << ":($4==0 ? $" << col << " : 1/0) with points lt " << train_lt
           << " title 'train', "
           << "'' using " << xcol << ":($4==1 ? $" << col << " : 1/0) with points lt " << held_lt
           << " title 'held out'\n";
      }
    }
    gp << "unset multiplot\n";
  }
  return gp.str();
}

std::string find_gnuplot() {
  const char* env = std::getenv("SINKWATCH_GNUPLOT");
  const std::string program = env != nullptr ? std::string(env) : std::string("gnuplot");
  if (program.empty()) {
    return {};
  }
  const std::string probe = "\"" + program + "\" -e \"exit\" >/dev/null 2>&1";
  return std::system(probe.c_str()) == 0 ? program : std::string();
}

namespace {

// The files a report directory holds (docs/diagnosis.md).
const char* const kReportFiles[] = {"residuals.dat", "residuals.gp", "summary.md", "residuals_vs_slip.svg",
                                    "residuals_vs_load.svg"};

// `text` as one single-quoted shell word.
std::string shell_quote(const std::string& text) {
  std::string q = "'";
  for (char c : text) {
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  }
  return q + "'";
}

// Replaces every `from` in `text` by `to`; throws when there is none (the
// script no longer has the form the plot run relies on).
std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  std::size_t count = 0;
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
    ++count;
  }
  if (count == 0) {
    throw std::logic_error("residuals.gp has no \"" + from + "\" to redirect to a temporary file");
  }
  return text;
}

std::string base_name(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace

void check_report_directory(const std::string& dir) {
  check_output_directory(dir);
  if (std::filesystem::is_directory(dir)) {
    for (const char* name : kReportFiles) {
      (void)check_output_path((std::filesystem::path(dir) / name).string());
    }
  }
}

namespace {

// residuals.dat: one line per row; residuals in noise units so that the
// channels share one axis (NaN where there is no fit: not_enough_data).
void write_residuals_dat(std::ostream& dat, const DiagnosisResult& r) {
  const RankedEffect* top = top_effect(r);
  dat << "# slip load_N sinkage_ratio heldout";
  for (const ChannelInfo& c : r.channels) {
    dat << " base_" << c.name;
  }
  for (const ChannelInfo& c : r.channels) {
    dat << " top_" << c.name;
  }
  dat << "  (residual = measured - model, in units of the row's noise in that channel)\n";
  std::vector<bool> held(r.rows.size(), false);
  for (std::size_t i : r.heldout) {
    held[i] = true;
  }
  dat << std::setprecision(8);
  auto scaled = [&](const FitResult* fit, std::size_t i, std::size_t c) {
    if (fit == nullptr || i >= fit->residuals.size()) {
      return std::string("NaN");
    }
    const double v = fit->residuals[i][c] / row_noise_of(r, i, c);
    return std::isfinite(v) ? num(v) : std::string("NaN");
  };
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    dat << r.rows[i].slip << ' ' << r.rows[i].load_n << ' ' << r.rows[i].sinkage_ratio << ' ' << (held[i] ? 1 : 0);
    for (std::size_t c = 0; c < r.channels.size(); ++c) {
      dat << ' ' << scaled(&r.base, i, c);
    }
    for (std::size_t c = 0; c < r.channels.size(); ++c) {
      dat << ' ' << scaled(top != nullptr ? &top->fit : nullptr, i, c);
    }
    dat << '\n';
  }
}

std::string report_summary(const DiagnosisResult& r, const std::string& gnuplot) {
  const RankedEffect* top = top_effect(r);
  std::ostringstream md;
  md << summary_markdown(r);
  if (gnuplot.empty()) {
    md << "\nNote: gnuplot was not found, so no plots were drawn; residuals.dat and residuals.gp are here "
          "(run `gnuplot residuals.gp` in this folder where gnuplot is installed).\n";
  } else {
    md << "\nPlots: residuals_vs_slip.svg, residuals_vs_load.svg (base and base + "
       << (top != nullptr ? top->effect : std::string("none")) << ").\n";
  }
  return md.str();
}

// gnuplot draws into temporaries beside the targets, from the temporary
// residuals.dat, through a copy of residuals.gp naming them; its exit status
// is checked before anything is renamed into place (files.commit() then
// checks that both plots were written).
void draw_plots(OutputFileSet& files, OutputFile& dat_file, const std::string& script, const std::string& dir,
                const std::string& gnuplot) {
  namespace fs = std::filesystem;
  const fs::path base(dir);
  dat_file.close();
  OutputFile& slip_svg = files.add((base / "residuals_vs_slip.svg").string());
  OutputFile& load_svg = files.add((base / "residuals_vs_load.svg").string());
  slip_svg.close();
  load_svg.close();
  std::string run_script = replace_all(script, "'residuals.dat'", "'" + base_name(dat_file.temporary_path()) + "'");
  run_script = replace_all(run_script, "'residuals_vs_slip.svg'", "'" + base_name(slip_svg.temporary_path()) + "'");
  run_script = replace_all(run_script, "'residuals_vs_load.svg'", "'" + base_name(load_svg.temporary_path()) + "'");
  // Neither is ever committed: both temporaries are removed at the end.
  OutputFile run_file((base / "residuals.gp").string());
  run_file.write(run_script);
  run_file.close();
  OutputFile log_file((base / "gnuplot.log").string());
  log_file.close();
  const std::string command = "cd " + shell_quote(fs::absolute(base).string()) + " && " + shell_quote(gnuplot) + " " +
                              shell_quote(base_name(run_file.temporary_path())) + " 2>" +
                              shell_quote(base_name(log_file.temporary_path()));
  const int status = std::system(command.c_str());
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::ifstream log(log_file.temporary_path());
    std::string messages((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
    if (messages.size() > 2000) {
      messages = messages.substr(0, 2000) + " ...";
    }
    throw std::runtime_error(dir + ": gnuplot (" + gnuplot + ") failed drawing the report's plots" +
                             (messages.empty() ? std::string() : ":\n" + messages) +
                             "\nno report file was written");
  }
}

}  // namespace

std::vector<std::string> write_report(const DiagnosisResult& r, const std::string& dir, const std::string& gnuplot) {
  namespace fs = std::filesystem;
  // Every file is written through a temporary (output_file.hpp) and renamed
  // only when all of them, the plots included, are complete: an error leaves
  // no half-written report.
  check_report_directory(dir);
  create_output_directory(dir);
  const fs::path base(dir);
  OutputFileSet files;
  OutputFile& dat_file = files.add((base / "residuals.dat").string());
  write_residuals_dat(dat_file.stream(), r);
  const std::string script = residuals_plot_script(r);
  files.add((base / "residuals.gp").string()).write(script);
  files.add((base / "summary.md").string()).write(report_summary(r, gnuplot));
  if (gnuplot.empty()) {
    files.commit();
    return {"gnuplot not found: wrote residuals.dat, residuals.gp and summary.md but no plots"};
  }
  draw_plots(files, dat_file, script, dir, gnuplot);
  files.commit();
  return {"plots written: " + (base / "residuals_vs_slip.svg").string() + ", " +
          (base / "residuals_vs_load.svg").string()};
}

}  // namespace ground
}  // namespace sinkwatch

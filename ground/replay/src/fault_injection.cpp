// Sensor faults injected into a telemetry log (fault_injection.hpp,
// docs/fault-injection.md).
#include "sinkwatch/ground/fault_injection.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

namespace sinkwatch::ground {
namespace {

// The reader's ranges (telemetry_log.cpp): a faulty value is kept inside them
// so that the faulty log can be written and read back.
constexpr double kMaxCurrentA = 1000.0;
constexpr double kMaxAngleDeg = 90.0;
constexpr double kMaxTimeS = 4294967.295;
// Row times are the CSV's, rounded to 1 ms: a window edge within this of a
// row's time includes the row.
constexpr double kTimeSlackS = 1e-6;

constexpr std::array<const char*, kFaultKinds> kKindNames{"stuck", "zero",  "dropout",   "spike",  "bias", "noise",
                                                          "freeze", "stall", "freewheel", "repeat", "jump"};
constexpr std::array<const char*, kFaultTargets> kTargetNames{
    "LF_current", "LM_current", "LR_current", "RF_current", "RM_current", "RR_current", "left",
    "right",      "imu",        "pitch",      "roll",       "joints",     "clock"};

// Which targets a kind accepts, as a bit per FaultTarget.
constexpr unsigned bit(FaultTarget t) { return 1U << static_cast<unsigned>(t); }
constexpr unsigned kCurrents = 0x3FU;
constexpr unsigned kSides = bit(FaultTarget::left) | bit(FaultTarget::right);
constexpr unsigned kAngles = bit(FaultTarget::imu) | bit(FaultTarget::pitch) | bit(FaultTarget::roll);

enum class ValueRule { none, optional, required };

struct KindRule {
  unsigned targets;
  ValueRule value;
  bool duration;  // whether +DURATION makes sense (a spike is one sample)
  bool positive;  // VALUE must be > 0 (else only non-zero)
};

// Indexed by FaultKind.
constexpr std::array<KindRule, kFaultKinds> kRules{{
    {kCurrents | kSides | kAngles | bit(FaultTarget::joints), ValueRule::none, true, false},      // stuck
    {kCurrents | kSides, ValueRule::none, true, false},                                            // zero
    {kCurrents | kSides | bit(FaultTarget::imu) | bit(FaultTarget::joints), ValueRule::none, true, false},  // dropout
    {kCurrents | bit(FaultTarget::pitch) | bit(FaultTarget::roll), ValueRule::optional, false, false},  // spike
    {kCurrents | kSides | kAngles, ValueRule::required, true, false},                              // bias
    {kCurrents | kSides | kAngles | bit(FaultTarget::joints), ValueRule::required, true, true},    // noise
    {kAngles | bit(FaultTarget::joints), ValueRule::none, true, false},                            // freeze
    {kCurrents | kSides, ValueRule::optional, true, true},                                         // stall
    {kCurrents | kSides, ValueRule::none, true, false},                                            // freewheel
    {bit(FaultTarget::clock), ValueRule::none, true, false},                                       // repeat
    {bit(FaultTarget::clock), ValueRule::required, false, true},  // jump: from START on (no way back)
}};

const KindRule& rule(FaultKind k) { return kRules[static_cast<std::size_t>(k)]; }

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// The shortest of %g that reads back as the same double, for spec texts.
std::string number_text(double v) {
  for (int digits = 6; digits < 17; ++digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) return buf;
  }
  return fmt("%.17g", v);
}

[[noreturn]] void fail(const std::string& spec, const std::string& problem) {
  throw FaultSpecError("fault '" + spec + "': " + problem);
}

template <std::size_t N>
std::string name_list(const std::array<const char*, N>& names, unsigned mask = ~0U) {
  std::string list;
  for (std::size_t i = 0; i < N; ++i) {
    if ((mask >> i) & 1U) list += (list.empty() ? "" : ", ") + std::string(names[i]);
  }
  return list;
}

// A finite number, with an optional trailing `unit` ("120s", "120").
double parse_number(const std::string& spec, const std::string& token, const char* what, const char* unit) {
  std::string t = token;
  if (*unit != '\0' && t.size() > 1 && t.back() == *unit) t.pop_back();
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size() || errno == ERANGE || !std::isfinite(v)) {
    fail(spec, std::string(what) + ": expected a finite number" + (*unit ? std::string(" of ") + unit : "") +
                   ", got '" + token + "'");
  }
  return v;
}

template <typename Enum, std::size_t N>
Enum lookup(const std::string& spec, const std::string& name, const std::array<const char*, N>& names,
            const char* what) {
  for (std::size_t i = 0; i < N; ++i) {
    if (name == names[i]) return static_cast<Enum>(i);
  }
  fail(spec, "unknown " + std::string(what) + " '" + name + "'; known: " + name_list(names));
}

// START[+DURATION][=VALUE] into the spec.
void parse_times_and_value(const std::string& spec, const std::string& rest, FaultSpec& f) {
  const std::size_t eq = rest.find('=');
  const std::string times = rest.substr(0, eq);
  if (eq != std::string::npos) f.value = parse_number(spec, rest.substr(eq + 1), "VALUE", "");
  const std::size_t plus = times.find('+');
  f.start_s = parse_number(spec, times.substr(0, plus), "START", "s");
  if (f.start_s < 0.0) fail(spec, "START must be >= 0 s, got " + number_text(f.start_s) + " s");
  if (plus == std::string::npos) return;
  f.duration_s = parse_number(spec, times.substr(plus + 1), "DURATION", "s");
  if (*f.duration_s <= 0.0) fail(spec, "DURATION must be > 0 s, got " + number_text(*f.duration_s) + " s");
}

// What the kind allows: its targets, a VALUE or not, a DURATION or not.
void check_rules(const std::string& spec, const FaultSpec& f) {
  const KindRule& r = rule(f.kind);
  const std::string kind = fault_kind_name(f.kind);
  if (((r.targets >> static_cast<unsigned>(f.target)) & 1U) == 0U) {
    fail(spec, kind + " does not apply to " + fault_target_name(f.target) + "; its targets: " +
                   name_list(kTargetNames, r.targets));
  }
  if (r.value == ValueRule::none && f.value) fail(spec, kind + " takes no =VALUE");
  if (r.value == ValueRule::required && !f.value) fail(spec, kind + " needs =VALUE (docs/fault-injection.md)");
  if (!r.duration && f.duration_s) {
    fail(spec, kind + (f.kind == FaultKind::spike ? " is one sample" : " lasts from START on") +
                   ": it takes no +DURATION");
  }
  if (f.value && r.positive && *f.value <= 0.0) fail(spec, kind + ": VALUE must be > 0, got " + number_text(*f.value));
  if (f.value && !r.positive && *f.value == 0.0) fail(spec, kind + ": VALUE 0 changes nothing");
}

}  // namespace

const char* fault_kind_name(FaultKind k) { return kKindNames.at(static_cast<std::size_t>(k)); }
const char* fault_target_name(FaultTarget t) { return kTargetNames.at(static_cast<std::size_t>(t)); }

std::string FaultSpec::text() const {
  std::string s = std::string(fault_kind_name(kind)) + ":" + fault_target_name(target) + "@" + number_text(start_s) + "s";
  if (duration_s) s += "+" + number_text(*duration_s) + "s";
  if (value) s += "=" + number_text(*value);
  return s;
}

FaultSpec parse_fault(const std::string& text) {
  const std::size_t b = text.find_first_not_of(" \t");
  const std::size_t e = text.find_last_not_of(" \t");
  const std::string spec = b == std::string::npos ? std::string() : text.substr(b, e - b + 1);
  if (spec.empty()) throw FaultSpecError("an empty fault: expected KIND:TARGET@START[+DURATION][=VALUE]");
  const std::size_t colon = spec.find(':');
  const std::size_t at = spec.find('@');
  if (colon == std::string::npos || at == std::string::npos || at < colon) {
    fail(spec, "expected KIND:TARGET@START[+DURATION][=VALUE], e.g. stuck:LM_current@120s+30s");
  }
  FaultSpec f;
  f.kind = lookup<FaultKind>(spec, spec.substr(0, colon), kKindNames, "kind");
  f.target = lookup<FaultTarget>(spec, spec.substr(colon + 1, at - colon - 1), kTargetNames, "target");
  parse_times_and_value(spec, spec.substr(at + 1), f);
  check_rules(spec, f);
  return f;
}

std::vector<FaultSpec> parse_faults(const std::string& list) {
  std::vector<FaultSpec> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = list.find(',', start);
    out.push_back(parse_fault(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

namespace {

// The measured numbers a fault can act on, per row.
enum class Slot { i0, i1, i2, i3, i4, i5, pitch, roll, rocker_l, rocker_r, bogie_l, bogie_r };

double& slot(TelemetryRow& r, Slot s) {
  switch (s) {
    case Slot::pitch: return r.pitch_deg;
    case Slot::roll: return r.roll_deg;
    case Slot::rocker_l: return r.rocker_deg[0];
    case Slot::rocker_r: return r.rocker_deg[1];
    case Slot::bogie_l: return r.bogie_deg[0];
    case Slot::bogie_r: return r.bogie_deg[1];
    default: return r.current_a[static_cast<std::size_t>(s)];
  }
}

bool is_current(Slot s) { return static_cast<int>(s) < static_cast<int>(Slot::pitch); }

bool is_missing(const TelemetryRow& r, Slot s) {
  if (is_current(s)) return r.current_missing[static_cast<std::size_t>(s)];
  return (s == Slot::pitch || s == Slot::roll) ? r.attitude_missing : r.joints_missing;
}

std::vector<Slot> slots_of(FaultTarget t) {
  switch (t) {
    case FaultTarget::left: return {Slot::i0, Slot::i1, Slot::i2};
    case FaultTarget::right: return {Slot::i3, Slot::i4, Slot::i5};
    case FaultTarget::imu: return {Slot::pitch, Slot::roll};
    case FaultTarget::pitch: return {Slot::pitch};
    case FaultTarget::roll: return {Slot::roll};
    case FaultTarget::joints: return {Slot::rocker_l, Slot::rocker_r, Slot::bogie_l, Slot::bogie_r};
    case FaultTarget::clock: return {};
    default: return {static_cast<Slot>(static_cast<int>(t))};
  }
}

double clamp_to_range(Slot s, double v) {
  const double limit = is_current(s) ? kMaxCurrentA : kMaxAngleDeg;
  return std::clamp(v, -limit, limit);
}

// SplitMix64, so that fault k of a seed has its own well-mixed stream.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// Gaussian draws from a bit-exact engine with our own conversion (Box-Muller):
// std::normal_distribution differs between standard libraries.
class Gauss {
 public:
  explicit Gauss(std::uint64_t seed) : engine_(seed) {}
  double operator()(double sd) {
    const double u1 = (static_cast<double>(engine_() >> 11) + 0.5) * (1.0 / 9007199254740992.0);
    const double u2 = static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0);
    return sd * std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }

 private:
  std::mt19937_64 engine_;
};

// The rows a fault changes, by their original times.
std::vector<std::size_t> window_rows(const FaultSpec& f, const std::vector<double>& times) {
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const bool after_start = times[i] >= f.start_s - kTimeSlackS;
    const bool before_end = !f.duration_s || times[i] < f.start_s + *f.duration_s - kTimeSlackS;
    if (after_start && before_end) rows.push_back(i);
    if (f.kind == FaultKind::spike && !rows.empty()) break;  // one sample
  }
  return rows;
}

double highest_current(const TelemetryLog& log) {
  double m = 0.0;
  for (const TelemetryRow& r : log.rows) {
    for (std::size_t w = 0; w < kTelemetryWheels; ++w) {
      if (!r.current_missing[w]) m = std::max(m, std::fabs(r.current_a[w]));
    }
  }
  return m;
}

// The VALUE a fault uses: the spec's, else the kind's default. `highest_a`
// is the clean log's highest |current| (an earlier spike must not make a
// later stall's default).
double fault_value(const FaultSpec& f, const TelemetryLog& log, const std::vector<std::size_t>& rows,
                   double highest_a) {
  if (f.value) return *f.value;
  if (f.kind == FaultKind::stall) return kStallFactor * highest_a;
  if (f.kind == FaultKind::spike && !rows.empty()) {
    const std::vector<Slot> slots = slots_of(f.target);
    if (!is_current(slots.front())) return kSpikeAngleDeg;
    const double i = log.rows[rows.front()].current_a[static_cast<std::size_t>(slots.front())];
    return std::max(kSpikeCurrentMinA, kSpikeCurrentFactor * std::fabs(i));
  }
  return 0.0;
}

void mark_missing(TelemetryRow& r, FaultTarget t) {
  for (const Slot s : slots_of(t)) {
    slot(r, s) = 0.0;
    if (is_current(s)) r.current_missing[static_cast<std::size_t>(s)] = true;
  }
  if (t == FaultTarget::imu) r.attitude_missing = true;
  if (t == FaultTarget::joints) r.joints_missing = true;
}

// The clock faults: stamps repeated, or shifted forward from START on.
void apply_clock(TelemetryLog& log, const FaultSpec& f, const std::vector<std::size_t>& rows, double value) {
  if (rows.empty()) return;
  if (f.kind == FaultKind::repeat) {
    const double held = log.rows[rows.front() > 0 ? rows.front() - 1 : 0].time_s;
    for (const std::size_t i : rows) log.rows[i].time_s = held;
    return;
  }
  // jump: every later stamp moves too, so the clock stays monotonic.
  for (std::size_t i = rows.front(); i < log.rows.size(); ++i) {
    log.rows[i].time_s = std::min(kMaxTimeS, log.rows[i].time_s + value);
  }
}

// One value of one row under a fault; `held` is the slot's value at START.
double faulty_value(const FaultSpec& f, double v, double held, double value, double drive_sign, Gauss& gauss) {
  switch (f.kind) {
    case FaultKind::stuck:
    case FaultKind::freeze: return held;
    case FaultKind::zero: return 0.0;
    case FaultKind::spike:
      // A current spike pushes in the driving direction unless VALUE gives a sign.
      return v + (f.value ? value : drive_sign * value);
    case FaultKind::bias: return v + value;
    case FaultKind::noise: return v + gauss(value);
    case FaultKind::stall: return drive_sign * value;
    case FaultKind::freewheel: return drive_sign * (kFreewheelCurrentA + gauss(kFreewheelNoiseA));
    default: return v;
  }
}

void apply_values(TelemetryLog& log, const FaultSpec& f, const std::vector<std::size_t>& rows, double value,
                  Gauss& gauss) {
  if (rows.empty()) return;
  if (f.kind == FaultKind::dropout) {
    for (const std::size_t i : rows) mark_missing(log.rows[i], f.target);
    return;
  }
  const std::vector<Slot> slots = slots_of(f.target);
  std::vector<double> held;
  for (const Slot s : slots) held.push_back(slot(log.rows[rows.front()], s));
  for (const std::size_t i : rows) {
    TelemetryRow& r = log.rows[i];
    for (std::size_t k = 0; k < slots.size(); ++k) {
      // A missing value stays missing (0 beside its flag); a current's
      // default spike, stall and free-wheel follow the driving direction.
      if (is_missing(r, slots[k])) continue;
      const double drive_sign = (is_current(slots[k]) && r.reverse) ? -1.0 : 1.0;
      double& v = slot(r, slots[k]);
      v = clamp_to_range(slots[k], faulty_value(f, v, held[k], value, drive_sign, gauss));
    }
  }
}

// "rows 601-751 (120.0-150.0 s)", or why none.
std::string rows_text(const TelemetryLog& log, const AppliedFault& a, const std::vector<double>& times) {
  if (a.rows == 0) return "no rows (the window lies outside the log)";
  const std::size_t last = a.first_row + a.rows - 1;
  return "rows " + std::to_string(a.first_row + 1) + "-" + std::to_string(last + 1) + " of " +
         std::to_string(log.rows.size()) + " (" + fmt("%.3f", times[a.first_row]) + "-" + fmt("%.3f", times[last]) +
         " s)";
}

}  // namespace

std::vector<AppliedFault> apply_faults(TelemetryLog& log, const std::vector<FaultSpec>& faults, std::uint64_t seed) {
  std::vector<double> times;
  for (const TelemetryRow& r : log.rows) times.push_back(r.time_s);
  const double highest_a = highest_current(log);
  std::vector<AppliedFault> applied;
  std::string texts;
  for (std::size_t k = 0; k < faults.size(); ++k) {
    const FaultSpec& f = faults[k];
    const std::vector<std::size_t> rows = window_rows(f, times);
    AppliedFault a{f, rows.size(), rows.empty() ? 0 : rows.front(), fault_value(f, log, rows, highest_a)};
    Gauss gauss(mix(mix(seed) ^ k));
    if (f.target == FaultTarget::clock) {
      apply_clock(log, f, rows, a.value);
    } else {
      apply_values(log, f, rows, a.value, gauss);
    }
    const bool valued = rule(f.kind).value != ValueRule::none;
    log.comments.push_back("injected fault " + f.text() + (valued ? " (value " + fmt("%g", a.value) + ")" : "") +
                           ": " + rows_text(log, a, times));
    texts += (texts.empty() ? "" : ",") + f.text();
    applied.push_back(a);
  }
  if (!faults.empty()) {
    const auto old = log.metadata.find("injected_faults");
    log.metadata["injected_faults"] = old != log.metadata.end() ? old->second + "," + texts : texts;
    log.metadata["fault_seed"] = std::to_string(seed);
  }
  return applied;
}

}  // namespace sinkwatch::ground

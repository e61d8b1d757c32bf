// The parameter table: defaults, range checks and the byte format
// (param_table.hpp; the layout is drawn in docs/flight.md).
#include "sinkwatch/flight/param_table.hpp"

#include "sinkwatch/fixedpoint/literal.hpp"
#include "sinkwatch/flight/byte_view.hpp"
#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/rover_limits.hpp"

namespace sinkwatch {
namespace flight {

namespace {

constexpr std::uint16_t kEstimatorBytes = 4U;
constexpr std::uint16_t kMotorBytes = 20U;
constexpr std::uint16_t kCorrectionHeaderBytes = 4U;
constexpr std::uint16_t kCorrectionRowBytes = 20U;
constexpr std::uint16_t kMonitorBytes = 44U;
constexpr std::uint16_t kEscapeBytes = 20U;
constexpr std::uint16_t kHealthBytes = 24U;
constexpr std::size_t kSectionHeaderBytes = 4U;
constexpr std::uint16_t kCoreSections = 5U;
// Capacity of ExtensionSection::bytes, a compile-time bound for its copy loop.
constexpr std::size_t kExtensionCapacity = sizeof(ExtensionSection::bytes);
static_assert(kExtensionCapacity == kExtensionMaxBytes, "ExtensionSection::bytes holds kExtensionMaxBytes bytes");

// Range limits of validate(). Each is a physical or numerical bound written
// down in docs/flight.md ("Parameter ranges").
constexpr GearRatio kMinGear{fx::constant<GearQ>(1.0)};
constexpr GearRatio kMaxGear{fx::constant<GearQ>(10000.0)};
constexpr Efficiency kMaxEfficiency{fx::constant<EfficiencyQ>(1.0)};
constexpr Efficiency kMinEfficiency{fx::constant<EfficiencyQ>(0.01)};
constexpr TorqueConstantNmPerA kMinKt{fx::constant<KtQ>(0.0001)};
constexpr TorqueConstantNmPerA kMaxKt{fx::constant<KtQ>(4.0)};
constexpr CurrentA kMaxNoLoadCurrent{fx::constant<CurrentQ>(100.0)};
constexpr CurrentA kMaxSensorCurrent{fx::constant<CurrentQ>(1000.0)};
constexpr WheelLoadN kMaxLoad{fx::constant<LoadQ>(30000.0)};
constexpr Ratio kMaxDpRatio{fx::constant<RatioQ>(2.0)};
constexpr Ratio kOne{fx::constant<RatioQ>(1.0)};
constexpr std::uint32_t kMaxStaleMs = 60000U;
constexpr std::uint32_t kMinPhaseMs = 100U;
constexpr std::uint32_t kMaxPhaseMs = 600000U;
constexpr std::uint8_t kMaxEscapeCycles = 100U;

// ---- little-endian byte writer and reader --------------------------------
// Both index the caller's buffer only through the bounded views of
// byte_view.hpp; a write past the capacity sets full(), a read past the end
// reads 0 (the decoder checks every length against the bytes left first).

class Writer {
 public:
  Writer(std::uint8_t* out, std::size_t capacity) noexcept : out_(out, capacity) {}
  void u8(std::uint8_t v) noexcept {
    if (!out_.set(pos_, v)) {
      // GCOVR_EXCL_START defensive, unreachable: encode() sizes the buffer first (docs/coverage.md)
      full_ = true;
      return;
      // GCOVR_EXCL_STOP
    }
    ++pos_;
  }
  void u16(std::uint16_t v) noexcept {
    u8(static_cast<std::uint8_t>(v & 0xFFU));
    u8(static_cast<std::uint8_t>((static_cast<std::uint32_t>(v) >> 8U) & 0xFFU));
  }
  void u32(std::uint32_t v) noexcept {
    for (std::uint32_t i = 0U; i < 4U; ++i) {
      u8(static_cast<std::uint8_t>((v >> (8U * i)) & 0xFFU));
    }
  }
  // Two's complement bits of v: the conversion to unsigned is defined modulo 2^32.
  void i32(std::int32_t v) noexcept { u32(static_cast<std::uint32_t>(v)); }
  [[nodiscard]] std::size_t pos() const noexcept { return pos_; }
  [[nodiscard]] bool full() const noexcept { return full_; }

 private:
  MutableByteView out_;
  std::size_t pos_{0U};
  bool full_{false};
};

class Reader {
 public:
  /// Reads `size` bytes at `in`, from byte `start` on.
  Reader(const std::uint8_t* in, std::size_t size, std::size_t start = 0U) noexcept : in_(in, size), pos_(start) {}
  std::uint8_t u8() noexcept {
    if (pos_ >= in_.size()) {
      return 0U;  // GCOVR_EXCL_LINE defensive, unreachable: decode() checks lengths first (docs/coverage.md)
    }
    const std::uint8_t v = in_.at(pos_);
    ++pos_;
    return v;
  }
  std::uint16_t u16() noexcept {
    const std::uint32_t lo = u8();
    const std::uint32_t hi = u8();
    return static_cast<std::uint16_t>(lo | (hi << 8U));
  }
  std::uint32_t u32() noexcept {
    std::uint32_t v = 0U;
    for (std::uint32_t i = 0U; i < 4U; ++i) {
      v |= static_cast<std::uint32_t>(u8()) << (8U * i);
    }
    return v;
  }
  std::int32_t i32() noexcept {
    const std::uint32_t u = u32();
    // Two's complement decode without an implementation-defined conversion.
    if (u <= 0x7FFFFFFFU) {
      return static_cast<std::int32_t>(u);
    }
    return static_cast<std::int32_t>(-static_cast<std::int64_t>(~u) - 1);
  }
  [[nodiscard]] std::size_t pos() const noexcept { return pos_; }

 private:
  ByteView in_;
  std::size_t pos_;
};

template <typename Quantity>
Quantity read_q(Reader& r) noexcept {
  return Quantity::from_raw(r.i32());
}

// ---- sections ----------------------------------------------------------

void write_section_header(Writer& w, SectionId id, std::uint16_t length) noexcept {
  w.u16(static_cast<std::uint16_t>(id));
  w.u16(length);
}

void write_motor(Writer& w, const MotorParams& m) noexcept {
  w.i32(m.gear_ratio.raw());
  w.i32(m.efficiency.raw());
  w.i32(m.kt_nm_per_a.raw());
  w.i32(m.no_load_current_a.raw());
  w.i32(m.current_abs_max_a.raw());
}

void read_motor(Reader& r, MotorParams& m) noexcept {
  m.gear_ratio = read_q<GearRatio>(r);
  m.efficiency = read_q<Efficiency>(r);
  m.kt_nm_per_a = read_q<TorqueConstantNmPerA>(r);
  m.no_load_current_a = read_q<CurrentA>(r);
  m.current_abs_max_a = read_q<CurrentA>(r);
}

std::uint16_t correction_bytes(std::uint8_t count) noexcept {
  return static_cast<std::uint16_t>(kCorrectionHeaderBytes + (kCorrectionRowBytes * count));
}

void write_correction(Writer& w, const CorrectionTable& c) noexcept {
  const std::uint8_t count = (c.count > kMaxCorrectionRows) ? kMaxCorrectionRows : c.count;
  w.u8(c.count);
  w.u8(0U);
  w.u16(0U);
  for (std::uint8_t i = 0U; i < count; ++i) {
    const CorrectionRow& row = c.rows[i];
    w.i32(row.load_n.raw());
    w.i32(row.c1.raw());
    w.i32(row.c2.raw());
    w.i32(row.c3.raw());
    w.i32(row.dp_max_ratio.raw());
  }
}

void write_monitor(Writer& w, const MonitorParams& m) noexcept {
  w.i32(m.allowed_sinkage_m.raw());
  w.i32(m.caution_sinkage_m.raw());
  w.i32(m.stop_sinkage_m.raw());
  w.i32(m.sinkage_hysteresis_m.raw());
  w.i32(m.current_caution_fraction.raw());
  w.i32(m.current_hysteresis_fraction.raw());
  w.i32(m.load_min_n.raw());
  w.i32(m.load_max_n.raw());
  w.u32(m.stale_timeout_ms);
  w.u8(m.window_m);
  w.u8(m.trip_n);
  w.u8(m.clear_n);
  w.u8(m.invalid_to_stop);
  w.u8(m.wheel_count);
  w.u8(m.rover_stop_k);
  w.u16(0U);
}

void read_monitor(Reader& r, MonitorParams& m) noexcept {
  m.allowed_sinkage_m = read_q<SinkageM>(r);
  m.caution_sinkage_m = read_q<SinkageM>(r);
  m.stop_sinkage_m = read_q<SinkageM>(r);
  m.sinkage_hysteresis_m = read_q<SinkageM>(r);
  m.current_caution_fraction = read_q<Ratio>(r);
  m.current_hysteresis_fraction = read_q<Ratio>(r);
  m.load_min_n = read_q<WheelLoadN>(r);
  m.load_max_n = read_q<WheelLoadN>(r);
  m.stale_timeout_ms = r.u32();
  m.window_m = r.u8();
  m.trip_n = r.u8();
  m.clear_n = r.u8();
  m.invalid_to_stop = r.u8();
  m.wheel_count = r.u8();
  m.rover_stop_k = r.u8();
}

/// Section 7: a table whose health checks are all zero (off) leaves it out,
/// so that tables written before it existed keep their bytes.
bool health_present(const HealthParams& h) noexcept {
  return (h.policy != LossPolicy::stop) || (h.stuck_cycles != 0U) || (h.implausible_cycles != 0U) ||
         (h.recover_cycles != 0U) || (h.max_blind_wheels != 0U) || (h.bridge_ms != 0U) ||
         (h.current_step_a.raw() != 0) || (h.attitude_step_rad.raw() != 0) || (h.joint_step_rad.raw() != 0);
}

void write_health(Writer& w, const HealthParams& h) noexcept {
  w.u8(static_cast<std::uint8_t>(h.policy));
  w.u8(h.stuck_cycles);
  w.u8(h.implausible_cycles);
  w.u8(h.recover_cycles);
  w.u8(h.max_blind_wheels);
  w.u8(0U);
  w.u16(0U);
  w.u32(h.bridge_ms);
  w.i32(h.current_step_a.raw());
  w.i32(h.attitude_step_rad.raw());
  w.i32(h.joint_step_rad.raw());
}

void write_escape(Writer& w, const EscapeParams& e) noexcept {
  w.u32(e.forward_phase_ms);
  w.u32(e.reverse_phase_ms);
  w.u8(e.max_cycles);
  w.u8(e.patience_cycles);
  w.u16(0U);
  w.i32(e.min_decrease_m.raw());
  w.i32(e.freed_sinkage_m.raw());
}

// ---- validation ----------------------------------------------------------

template <typename T>
bool within(T v, T lo, T hi) noexcept {
  return (v >= lo) && (v <= hi);
}

RejectReason validate_motor(const MotorParams& m) noexcept {
  if (!within(m.gear_ratio, kMinGear, kMaxGear)) {
    return RejectReason::gear_ratio_out_of_range;
  }
  if (!within(m.efficiency, kMinEfficiency, kMaxEfficiency)) {
    return RejectReason::efficiency_out_of_range;
  }
  if (!within(m.kt_nm_per_a, kMinKt, kMaxKt)) {
    return RejectReason::torque_constant_out_of_range;
  }
  if (!within(m.no_load_current_a, CurrentA::zero(), kMaxNoLoadCurrent)) {
    return RejectReason::no_load_current_out_of_range;
  }
  if ((m.current_abs_max_a <= m.no_load_current_a) || (m.current_abs_max_a > kMaxSensorCurrent)) {
    return RejectReason::current_range_out_of_range;
  }
  return RejectReason::ok;
}

RejectReason validate_correction(const CorrectionTable& c) noexcept {
  if ((c.count == 0U) || (c.count > kMaxCorrectionRows)) {
    return RejectReason::correction_count_out_of_range;
  }
  for (std::uint8_t i = 0U; i < c.count; ++i) {
    const CorrectionRow& row = c.rows[i];
    if ((row.load_n <= WheelLoadN::zero()) || (row.load_n > kMaxLoad)) {
      return RejectReason::load_breakpoint_out_of_range;
    }
    if ((i > 0U) && (row.load_n <= c.rows[i - 1U].load_n)) {
      return RejectReason::load_breakpoints_not_increasing;
    }
    if (!within(row.c1, kMinC12, kMaxC12)) {
      return RejectReason::c1_out_of_range;
    }
    if (!within(row.c2, kMinC12, kMaxC12)) {
      return RejectReason::c2_out_of_range;
    }
    if (!within(row.c3, kMinC3, kMaxC3)) {
      return RejectReason::c3_out_of_range;
    }
    if ((row.dp_max_ratio <= Ratio::zero()) || (row.dp_max_ratio > kMaxDpRatio)) {
      return RejectReason::dp_max_out_of_range;
    }
  }
  return RejectReason::ok;
}

// The sinkage thresholds, against each other and the wheel radius.
RejectReason validate_monitor_sinkage(const MonitorParams& m, LengthM radius_m) noexcept {
  const SinkageM radius_as_sinkage = SinkageM::from_raw(radius_m.raw());  // same format, same unit
  if ((m.allowed_sinkage_m <= SinkageM::zero()) || (m.allowed_sinkage_m > radius_as_sinkage)) {
    return RejectReason::allowed_sinkage_out_of_range;
  }
  if ((m.caution_sinkage_m <= SinkageM::zero()) || (m.caution_sinkage_m >= m.stop_sinkage_m)) {
    return RejectReason::caution_sinkage_out_of_range;
  }
  if (m.stop_sinkage_m > radius_as_sinkage) {
    return RejectReason::stop_sinkage_out_of_range;
  }
  if ((m.sinkage_hysteresis_m < SinkageM::zero()) || (m.sinkage_hysteresis_m >= m.caution_sinkage_m)) {
    return RejectReason::sinkage_hysteresis_out_of_range;
  }
  return RejectReason::ok;
}

// The current fractions, the load envelope and the staleness timeout.
RejectReason validate_monitor_current_and_load(const MonitorParams& m) noexcept {
  if ((m.current_caution_fraction <= Ratio::zero()) || (m.current_caution_fraction > kOne)) {
    return RejectReason::current_caution_fraction_out_of_range;
  }
  if ((m.current_hysteresis_fraction < Ratio::zero()) ||
      (m.current_hysteresis_fraction >= m.current_caution_fraction)) {
    return RejectReason::current_hysteresis_out_of_range;
  }
  if ((m.load_min_n <= WheelLoadN::zero()) || (m.load_max_n <= m.load_min_n) || (m.load_max_n > kMaxLoad)) {
    return RejectReason::load_envelope_out_of_range;
  }
  if ((m.stale_timeout_ms == 0U) || (m.stale_timeout_ms > kMaxStaleMs)) {
    return RejectReason::stale_timeout_out_of_range;
  }
  return RejectReason::ok;
}

// The persistence window, its counts and the wheel counts.
RejectReason validate_monitor_counts(const MonitorParams& m) noexcept {
  if ((m.window_m == 0U) || (m.window_m > kMaxWindow)) {
    return RejectReason::window_out_of_range;
  }
  if ((m.trip_n == 0U) || (m.trip_n > m.window_m)) {
    return RejectReason::trip_count_out_of_range;
  }
  if ((m.clear_n == 0U) || (m.clear_n > m.window_m)) {
    return RejectReason::clear_count_out_of_range;
  }
  if (m.invalid_to_stop == 0U) {
    return RejectReason::invalid_limit_out_of_range;
  }
  if ((m.wheel_count == 0U) || (m.wheel_count > kMaxWheels)) {
    return RejectReason::wheel_count_out_of_range;
  }
  if ((m.rover_stop_k == 0U) || (m.rover_stop_k > m.wheel_count)) {
    return RejectReason::rover_stop_k_out_of_range;
  }
  return RejectReason::ok;
}

// In the order of the struct's fields, as validate() promises.
RejectReason validate_monitor(const MonitorParams& m, LengthM radius_m) noexcept {
  RejectReason r = validate_monitor_sinkage(m, radius_m);
  if (r != RejectReason::ok) {
    return r;
  }
  r = validate_monitor_current_and_load(m);
  if (r != RejectReason::ok) {
    return r;
  }
  return validate_monitor_counts(m);
}

RejectReason validate_escape(const EscapeParams& e, const MonitorParams& m) noexcept {
  if (!within(e.forward_phase_ms, kMinPhaseMs, kMaxPhaseMs) || !within(e.reverse_phase_ms, kMinPhaseMs, kMaxPhaseMs)) {
    return RejectReason::escape_phase_out_of_range;
  }
  if ((e.max_cycles == 0U) || (e.max_cycles > kMaxEscapeCycles)) {
    return RejectReason::escape_cycles_out_of_range;
  }
  if ((e.patience_cycles == 0U) || (e.patience_cycles > e.max_cycles)) {
    return RejectReason::escape_patience_out_of_range;
  }
  if ((e.min_decrease_m < SinkageM::zero()) || (e.min_decrease_m >= m.stop_sinkage_m)) {
    return RejectReason::escape_decrease_out_of_range;
  }
  if ((e.freed_sinkage_m <= SinkageM::zero()) || (e.freed_sinkage_m >= m.stop_sinkage_m)) {
    return RejectReason::escape_freed_out_of_range;
  }
  return RejectReason::ok;
}


constexpr std::uint32_t kMaxBridgeMs = 60000U;
// A quarter turn in one sample is beyond any attitude or joint change.
constexpr AngleRad kMaxHealthStepRad{fx::constant<AngleQ>(1.5707963267948966)};

RejectReason validate_health(const HealthParams& h, const MotorParams& motor, const MonitorParams& m) noexcept {
  if ((h.policy != LossPolicy::stop) && (h.policy != LossPolicy::continue_degraded)) {
    return RejectReason::health_policy_out_of_range;
  }
  // Every wheel blind would be a drive with no evidence at all.
  if (h.max_blind_wheels >= m.wheel_count) {
    return RejectReason::health_blind_wheels_out_of_range;
  }
  if ((h.current_step_a < CurrentA::zero()) || (h.current_step_a > motor.current_abs_max_a) ||
      (h.attitude_step_rad < AngleRad::zero()) || (h.attitude_step_rad > kMaxHealthStepRad) ||
      (h.joint_step_rad < AngleRad::zero()) || (h.joint_step_rad > kMaxHealthStepRad)) {
    return RejectReason::health_step_out_of_range;
  }
  if (h.bridge_ms > kMaxBridgeMs) {
    return RejectReason::health_bridge_out_of_range;
  }
  return RejectReason::ok;
}

}  // namespace

// ---- defaults --------------------------------------------------------------

namespace {

// Built in a constant expression, so every fx::constant is evaluated by the
// compiler and no floating point reaches the target.
constexpr ParameterTable make_default_table() noexcept {
  ParameterTable t{};
  t.table_version = 1U;
  t.wheel_radius_m = LengthM(fx::constant<LengthQ>(0.15));

  t.motor.gear_ratio = GearRatio(fx::constant<GearQ>(400.0));
  t.motor.efficiency = Efficiency(fx::constant<EfficiencyQ>(0.6));
  t.motor.kt_nm_per_a = TorqueConstantNmPerA(fx::constant<KtQ>(0.025));
  t.motor.no_load_current_a = CurrentA(fx::constant<CurrentQ>(0.1));
  t.motor.current_abs_max_a = CurrentA(fx::constant<CurrentQ>(10.0));

  // Table 2: soil-bin masses times Earth's gravity (the soil bin's, from
  // rover_limits.hpp); C1 = C2 = 1. These doubles
  // exist only while the compiler evaluates kDefaultTable (below), a
  // constexpr object: deviation D-01 (docs/misra.md). The firmware symbol
  // check proves no floating point is left in the object code.
  constexpr double kG = limits::kGravityEarthMps2;
  constexpr double kMassKg[5] = {3.0, 7.0, 10.0, 15.0, 20.0};
  constexpr double kC3[5] = {0.20, 0.15, 0.13, 0.13, 0.13};
  t.correction.count = 5U;
  for (std::uint8_t i = 0U; i < 5U; ++i) {
    t.correction.rows[i] = CorrectionRow{WheelLoadN(fx::constant<LoadQ>(kMassKg[i] * kG)), Ratio(fx::constant<RatioQ>(1.0)),
                                         Ratio(fx::constant<RatioQ>(1.0)), Ratio(fx::constant<RatioQ>(kC3[i])),
                                         Ratio(fx::constant<RatioQ>(0.5))};
  }

  t.monitor.allowed_sinkage_m = SinkageM(fx::constant<LengthQ>(0.045));
  t.monitor.caution_sinkage_m = SinkageM(fx::constant<LengthQ>(0.03));
  t.monitor.stop_sinkage_m = SinkageM(fx::constant<LengthQ>(0.045));
  t.monitor.sinkage_hysteresis_m = SinkageM(fx::constant<LengthQ>(0.005));
  t.monitor.current_caution_fraction = Ratio(fx::constant<RatioQ>(0.9));
  t.monitor.current_hysteresis_fraction = Ratio(fx::constant<RatioQ>(0.05));
  t.monitor.load_min_n = WheelLoadN(fx::constant<LoadQ>(1.0));
  t.monitor.load_max_n = WheelLoadN(fx::constant<LoadQ>(2000.0));
  t.monitor.stale_timeout_ms = 500U;
  t.monitor.window_m = 8U;
  t.monitor.trip_n = 3U;
  t.monitor.clear_n = 6U;
  t.monitor.invalid_to_stop = 10U;
  t.monitor.wheel_count = kMaxWheels;
  t.monitor.rover_stop_k = 1U;

  t.escape.forward_phase_ms = 5000U;
  t.escape.reverse_phase_ms = 5000U;
  t.escape.max_cycles = 10U;
  t.escape.patience_cycles = 2U;
  t.escape.min_decrease_m = SinkageM(fx::constant<LengthQ>(0.002));
  t.escape.freed_sinkage_m = SinkageM(fx::constant<LengthQ>(0.02));

  t.rover_geometry.present = false;
  t.rover_geometry.length = 0U;

  // Section 7 (docs/fault-tolerance.md): at 5 Hz, stuck after 2 s of
  // identical samples, a free-wheeling motor after 1 s, recovered after 1 s;
  // an IMU or joint fault bridged for 2 s; spikes beyond 1 A, 2 deg, 3 deg
  // in one sample (Yutu's currents stay below 1 A; the soil changes them by
  // tenths of an ampere per sample).
  t.health.policy = LossPolicy::stop;
  t.health.stuck_cycles = 10U;
  t.health.implausible_cycles = 5U;
  t.health.recover_cycles = 5U;
  t.health.max_blind_wheels = 1U;
  t.health.bridge_ms = 2000U;
  t.health.current_step_a = CurrentA(fx::constant<CurrentQ>(1.0));
  t.health.attitude_step_rad = AngleRad(fx::constant<AngleQ>(0.034906585039886591));
  t.health.joint_step_rad = AngleRad(fx::constant<AngleQ>(0.052359877559829883));
  return t;
}

constexpr ParameterTable kDefaultTable = make_default_table();
constexpr Ratio kEq15C3{fx::constant<RatioQ>(0.13)};

}  // namespace

ParameterTable default_parameter_table() noexcept { return kDefaultTable; }

ParameterTable eq15_parameter_table() noexcept {
  ParameterTable t = default_parameter_table();
  for (std::uint8_t i = 0U; i < t.correction.count; ++i) {
    t.correction.rows[i].c3 = kEq15C3;
  }
  return t;
}

// ---- validate, encode, decode ----------------------------------------------

RejectReason validate(const ParameterTable& t) noexcept {
  if ((t.wheel_radius_m < kMinRadiusM) || (t.wheel_radius_m > kMaxRadiusM)) {
    return RejectReason::radius_out_of_range;
  }
  RejectReason r = validate_motor(t.motor);
  if (r != RejectReason::ok) {
    return r;
  }
  r = validate_correction(t.correction);
  if (r != RejectReason::ok) {
    return r;
  }
  r = validate_monitor(t.monitor, t.wheel_radius_m);
  if (r != RejectReason::ok) {
    return r;
  }
  r = validate_escape(t.escape, t.monitor);
  if (r != RejectReason::ok) {
    return r;
  }
  r = validate_health(t.health, t.motor, t.monitor);
  if (r != RejectReason::ok) {
    return r;
  }
  if (t.rover_geometry.present && (t.rover_geometry.length > kExtensionMaxBytes)) {
    return RejectReason::extension_too_long;
  }
  return RejectReason::ok;
}

EncodeResult encode(const ParameterTable& t, std::uint8_t* out, std::size_t capacity) noexcept {
  if (out == nullptr) {
    return EncodeResult{0U, RejectReason::null_buffer};
  }
  if (t.rover_geometry.present && (t.rover_geometry.length > kExtensionMaxBytes)) {
    return EncodeResult{0U, RejectReason::extension_too_long};
  }
  const std::uint8_t rows = (t.correction.count > kMaxCorrectionRows) ? kMaxCorrectionRows : t.correction.count;
  const bool with_health = health_present(t.health);
  const std::uint16_t sections =
      static_cast<std::uint16_t>(kCoreSections + (t.rover_geometry.present ? 1U : 0U) + (with_health ? 1U : 0U));
  std::size_t total = kTableHeaderBytes + (kCoreSections * kSectionHeaderBytes) + kEstimatorBytes + kMotorBytes +
                      correction_bytes(rows) + kMonitorBytes + kEscapeBytes + kTableCrcBytes;
  if (t.rover_geometry.present) {
    total += kSectionHeaderBytes + t.rover_geometry.length;
  }
  if (with_health) {
    total += kSectionHeaderBytes + kHealthBytes;
  }
  if (total > capacity) {
    return EncodeResult{0U, RejectReason::buffer_too_small};
  }
  Writer w(out, capacity);
  for (std::uint8_t b : kTableMagic) {
    w.u8(b);
  }
  w.u16(kTableFormatVersion);
  w.u16(t.table_version);
  w.u32(static_cast<std::uint32_t>(total));
  w.u16(sections);
  w.u16(0U);

  write_section_header(w, SectionId::estimator, kEstimatorBytes);
  w.i32(t.wheel_radius_m.raw());
  write_section_header(w, SectionId::motor, kMotorBytes);
  write_motor(w, t.motor);
  write_section_header(w, SectionId::correction, correction_bytes(rows));
  write_correction(w, t.correction);
  write_section_header(w, SectionId::monitor, kMonitorBytes);
  write_monitor(w, t.monitor);
  write_section_header(w, SectionId::escape, kEscapeBytes);
  write_escape(w, t.escape);
  if (t.rover_geometry.present) {
    write_section_header(w, SectionId::rover_geometry, t.rover_geometry.length);
    for (std::uint16_t i = 0U; i < t.rover_geometry.length; ++i) {
      w.u8(t.rover_geometry.bytes[i]);
    }
  }
  if (with_health) {
    write_section_header(w, SectionId::health, kHealthBytes);
    write_health(w, t.health);
  }
  const std::uint32_t crc = crc32(out, w.pos());
  w.u32(crc);
  if (w.full() || (w.pos() != total)) {
    // GCOVR_EXCL_START defensive, unreachable: sized above (docs/coverage.md)
    return EncodeResult{0U, RejectReason::buffer_too_small};
    // GCOVR_EXCL_STOP
  }
  return EncodeResult{total, RejectReason::ok};
}

namespace {

// "SWPT" as the little-endian u32 the reader assembles from kTableMagic.
constexpr std::uint32_t kTableMagicWord =
    static_cast<std::uint32_t>(kTableMagic[0]) | (static_cast<std::uint32_t>(kTableMagic[1]) << 8U) |
    (static_cast<std::uint32_t>(kTableMagic[2]) << 16U) | (static_cast<std::uint32_t>(kTableMagic[3]) << 24U);

constexpr std::uint16_t kMaxSectionId = 7U;
// Bit id of a section set, ids 1..kCoreSections: the sections every table has.
constexpr std::uint32_t kCoreSectionBits = (1U << (kCoreSections + 1U)) - 2U;

// The header after the size checks: magic, format version, table version,
// total length, section count, reserved.
RejectReason read_table_header(Reader& r, std::size_t size, std::uint16_t& table_version,
                               std::uint16_t& section_count) noexcept {
  if (r.u32() != kTableMagicWord) {
    return RejectReason::bad_magic;
  }
  if (r.u16() != kTableFormatVersion) {
    return RejectReason::unsupported_format_version;
  }
  table_version = r.u16();
  if (r.u32() != size) {
    return RejectReason::length_mismatch;
  }
  section_count = r.u16();
  if (r.u16() != 0U) {
    return RejectReason::reserved_not_zero;
  }
  return RejectReason::ok;
}

// ---- section payloads: each checks its length before it reads ------------

RejectReason read_estimator_section(Reader& r, std::uint16_t length, LengthM& radius_m) noexcept {
  if (length != kEstimatorBytes) {
    return RejectReason::section_length_mismatch;
  }
  radius_m = read_q<LengthM>(r);
  return RejectReason::ok;
}

RejectReason read_motor_section(Reader& r, std::uint16_t length, MotorParams& m) noexcept {
  if (length != kMotorBytes) {
    return RejectReason::section_length_mismatch;
  }
  read_motor(r, m);
  return RejectReason::ok;
}

RejectReason read_correction_section(Reader& r, std::uint16_t length, CorrectionTable& c) noexcept {
  if (length < kCorrectionHeaderBytes) {
    return RejectReason::section_length_mismatch;
  }
  c.count = r.u8();
  const std::uint8_t reserved8 = r.u8();
  const std::uint16_t reserved16 = r.u16();
  // The row count's range and the length it implies come before the
  // reserved bytes: a wrong count is the more useful reason.
  if ((c.count == 0U) || (c.count > kMaxCorrectionRows)) {
    return RejectReason::correction_count_out_of_range;
  }
  if (length != correction_bytes(c.count)) {
    return RejectReason::section_length_mismatch;
  }
  for (std::uint8_t i = 0U; i < c.count; ++i) {
    CorrectionRow& row = c.rows[i];
    row.load_n = read_q<WheelLoadN>(r);
    row.c1 = read_q<Ratio>(r);
    row.c2 = read_q<Ratio>(r);
    row.c3 = read_q<Ratio>(r);
    row.dp_max_ratio = read_q<Ratio>(r);
  }
  if ((reserved8 != 0U) || (reserved16 != 0U)) {
    return RejectReason::reserved_not_zero;
  }
  return RejectReason::ok;
}

RejectReason read_monitor_section(Reader& r, std::uint16_t length, MonitorParams& m) noexcept {
  if (length != kMonitorBytes) {
    return RejectReason::section_length_mismatch;
  }
  read_monitor(r, m);
  if (r.u16() != 0U) {
    return RejectReason::reserved_not_zero;
  }
  return RejectReason::ok;
}

RejectReason read_escape_section(Reader& r, std::uint16_t length, EscapeParams& e) noexcept {
  if (length != kEscapeBytes) {
    return RejectReason::section_length_mismatch;
  }
  // The reserved u16 sits after the two cycle counts: read it in place.
  e.forward_phase_ms = r.u32();
  e.reverse_phase_ms = r.u32();
  e.max_cycles = r.u8();
  e.patience_cycles = r.u8();
  const std::uint16_t reserved = r.u16();
  e.min_decrease_m = read_q<SinkageM>(r);
  e.freed_sinkage_m = read_q<SinkageM>(r);
  if (reserved != 0U) {
    return RejectReason::reserved_not_zero;
  }
  return RejectReason::ok;
}

RejectReason read_extension_section(Reader& r, std::uint16_t length, ExtensionSection& x) noexcept {
  if (length > kExtensionMaxBytes) {
    return RejectReason::extension_too_long;
  }
  x.present = true;
  x.length = length;
  // The array's own size bounds the loop as well as the length checked above
  // (the same bytes are copied). GCC 12 at -O3 vectorizes this copy and,
  // with `i < length` alone, loses the length's range in the vector epilogue:
  // a false -Wstringop-overflow ("writing 16 bytes into a region of size 15").
  for (std::size_t i = 0U; (i < kExtensionCapacity) && (i < length); ++i) {
    x.bytes[i] = r.u8();
  }
  return RejectReason::ok;
}

RejectReason read_health_section(Reader& r, std::uint16_t length, HealthParams& h) noexcept {
  if (length != kHealthBytes) {
    return RejectReason::section_length_mismatch;
  }
  const std::uint8_t policy = r.u8();
  h.stuck_cycles = r.u8();
  h.implausible_cycles = r.u8();
  h.recover_cycles = r.u8();
  h.max_blind_wheels = r.u8();
  const std::uint8_t reserved8 = r.u8();
  const std::uint16_t reserved16 = r.u16();
  h.bridge_ms = r.u32();
  h.current_step_a = read_q<CurrentA>(r);
  h.attitude_step_rad = read_q<AngleRad>(r);
  h.joint_step_rad = read_q<AngleRad>(r);
  if (policy > static_cast<std::uint8_t>(LossPolicy::continue_degraded)) {
    return RejectReason::health_policy_out_of_range;
  }
  h.policy = static_cast<LossPolicy>(policy);
  if ((reserved8 != 0U) || (reserved16 != 0U)) {
    return RejectReason::reserved_not_zero;
  }
  return RejectReason::ok;
}

RejectReason read_section_payload(Reader& r, SectionId id, std::uint16_t length, ParameterTable& t) noexcept {
  switch (id) {
    case SectionId::estimator:
      return read_estimator_section(r, length, t.wheel_radius_m);
    case SectionId::motor:
      return read_motor_section(r, length, t.motor);
    case SectionId::correction:
      return read_correction_section(r, length, t.correction);
    case SectionId::monitor:
      return read_monitor_section(r, length, t.monitor);
    case SectionId::escape:
      return read_escape_section(r, length, t.escape);
    case SectionId::rover_geometry:
      return read_extension_section(r, length, t.rover_geometry);
    case SectionId::health:
      return read_health_section(r, length, t.health);
    // GCOVR_EXCL_START MISRA 16.4.1's default; read_section() refuses other ids first (docs/coverage.md)
    default:
      return RejectReason::unknown_section;
      // GCOVR_EXCL_STOP
  }
}

// One section, header and payload; `r` stands at its header, `crc_at` is
// where the sections end. `seen` collects bit id of every section read.
RejectReason read_section(Reader& r, std::size_t crc_at, ParameterTable& t, std::uint32_t& seen) noexcept {
  if ((crc_at - r.pos()) < kSectionHeaderBytes) {
    return RejectReason::section_truncated;
  }
  const std::uint16_t id = r.u16();
  const std::uint16_t length = r.u16();
  if ((crc_at - r.pos()) < length) {
    return RejectReason::section_truncated;
  }
  if ((id == 0U) || (id > kMaxSectionId)) {
    return RejectReason::unknown_section;
  }
  const std::uint32_t bit = 1U << static_cast<std::uint32_t>(id);
  if ((seen & bit) != 0U) {
    return RejectReason::duplicate_section;
  }
  seen |= bit;
  const std::size_t start = r.pos();
  const RejectReason reason = read_section_payload(r, static_cast<SectionId>(id), length, t);
  if (reason != RejectReason::ok) {
    return reason;
  }
  if ((r.pos() - start) != length) {
    // GCOVR_EXCL_START defensive, unreachable: lengths checked per id (docs/coverage.md)
    return RejectReason::section_length_mismatch;
    // GCOVR_EXCL_STOP
  }
  return RejectReason::ok;
}

// Every section up to the CRC, then the count and the core sections.
RejectReason read_sections(Reader& r, std::size_t crc_at, std::uint16_t section_count, ParameterTable& t) noexcept {
  // At most one section per id, ids 1..7, so at most 7 iterations do work;
  // the loop bound also covers a corrupt count that passed the CRC.
  std::uint32_t seen = 0U;
  std::uint16_t parsed = 0U;
  while ((r.pos() < crc_at) && (parsed <= kMaxSectionId)) {
    const RejectReason reason = read_section(r, crc_at, t, seen);
    if (reason != RejectReason::ok) {
      return reason;
    }
    ++parsed;
  }
  if ((r.pos() != crc_at) || (parsed != section_count)) {
    return RejectReason::section_count_mismatch;
  }
  if ((seen & kCoreSectionBits) != kCoreSectionBits) {
    return RejectReason::missing_section;
  }
  return RejectReason::ok;
}

}  // namespace

RejectReason decode(const std::uint8_t* bytes, std::size_t size, ParameterTable& out,
                    ExtensionValidator extension) noexcept {
  if (bytes == nullptr) {
    return RejectReason::null_buffer;
  }
  if (size < (kTableHeaderBytes + kTableCrcBytes)) {
    return RejectReason::too_short;
  }
  if (size > kMaxTableBytes) {
    return RejectReason::too_long;
  }
  Reader r(bytes, size);
  ParameterTable t{};
  std::uint16_t section_count = 0U;
  RejectReason reason = read_table_header(r, size, t.table_version, section_count);
  if (reason != RejectReason::ok) {
    return reason;
  }
  const std::size_t crc_at = size - kTableCrcBytes;
  Reader crc_reader(bytes, size, crc_at);
  if (crc_reader.u32() != crc32(bytes, crc_at)) {
    return RejectReason::crc_mismatch;
  }
  reason = read_sections(r, crc_at, section_count, t);
  if (reason != RejectReason::ok) {
    return reason;
  }
  reason = validate(t);
  if (reason != RejectReason::ok) {
    return reason;
  }
  if (t.rover_geometry.present && (extension != nullptr) && !extension(t.rover_geometry)) {
    return RejectReason::extension_rejected;
  }
  out = t;
  return RejectReason::ok;
}

// ---- the store --------------------------------------------------------------

ParameterStore::ParameterStore() noexcept
    : active_(default_parameter_table()), active_crc_(0U), rejected_count_(0U), last_rejection_(RejectReason::ok) {}

RejectReason ParameterStore::load(const std::uint8_t* bytes, std::size_t size, ExtensionValidator extension) noexcept {
  ParameterTable candidate{};
  const RejectReason reason = decode(bytes, size, candidate, extension);
  if (reason != RejectReason::ok) {
    if (rejected_count_ < 0xFFFFFFFFU) {
      ++rejected_count_;
    }
    last_rejection_ = reason;
    return reason;
  }
  active_ = candidate;
  // decode() checked the CRC at size - 4: the bytes are there.
  Reader crc_reader(bytes, size, size - kTableCrcBytes);
  active_crc_ = crc_reader.u32();
  last_rejection_ = RejectReason::ok;
  return reason;
}

}  // namespace flight
}  // namespace sinkwatch

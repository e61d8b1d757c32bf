// Drawbar pull from the vehicle force balance; see drawbar_pull.hpp and
// docs/rover-loads.md, section 6. Twin: ground/reference/src/rover_loads.cpp.
#include "sinkwatch/flight/drawbar_pull.hpp"

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"

namespace sinkwatch {
namespace flight {
namespace {

using W = WideQ;

constexpr Ratio kMaxSlip{fx::constant<RatioQ>(1.0)};

DrawbarResult failed(DrawbarStatus status) noexcept {
  DrawbarResult r{};
  r.status = status;
  return r;
}

bool ratio_in_range(Ratio r) noexcept { return (r.raw() > 0) && (r <= kMaxDpMaxRatio); }

/// The acceleration, the slope, the slip and every ratio and load are in
/// their accepted ranges (the parameters are already validated).
bool inputs_in_range(const RoverParams& params, const WheelLoadResult& loads, const DrawbarInput& input) noexcept {
  const bool accel_ok = (input.accel_mps2 <= kMaxAbsAccel) && (input.accel_mps2.raw() >= -kMaxAbsAccel.raw());
  const bool pitch_ok = (input.pitch_rad <= params.attitude_limit_rad) &&
                        (input.pitch_rad.raw() >= -params.attitude_limit_rad.raw());
  const bool slip_ok = !input.slip_known || (input.slip <= kMaxSlip);
  if (!accel_ok || !pitch_ok || !slip_ok) {
    return false;
  }
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    if (!ratio_in_range(input.dp_max_ratio[i]) || (loads.load_n[i].raw() < 0)) {
      return false;
    }
  }
  return true;
}

/// The pulls for usable loads and parameters that passed
/// validate_rover_params().
DrawbarResult pulls_of_valid(const RoverParams& params, const WheelLoadResult& loads,
                             const DrawbarInput& input) noexcept {
  if (!inputs_in_range(params, loads, input)) {
    return failed(DrawbarStatus::invalid_input);
  }
  // sum W in raw Q15.16 units: six values in [0, 2^31) sum below 2^34.
  std::uint64_t load_sum = 0U;
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    load_sum += static_cast<std::uint64_t>(loads.load_n[i].raw());
  }
  if (load_sum == 0U) {
    return failed(DrawbarStatus::invalid_loads);
  }
  fx::Status st;
  // m (a + g sin(pitch)): the along-path force the tractions must supply.
  // The loads' sine when they were computed at this pitch (the step's case):
  // the same bits as computing it here.
  const fx::Q1_30 sin_pitch =
      (loads.pitch_rad == input.pitch_rad) ? loads.sin_pitch : fx::sin(input.pitch_rad.q(), st);
  // Mass and gravity are positive (validated), |a| <= 10 (inputs_in_range).
  const std::int64_t total = detail::along_force_raw(static_cast<std::uint32_t>(params.mass_kg.raw()),
                                                     static_cast<std::uint32_t>(params.gravity_mps2.raw()),
                                                     sin_pitch.raw(), input.accel_mps2.raw());
  const DrawbarPullN total_n{fx::rescale<LoadQ>(W::from_raw(total), st)};
  const bool saturated = input.slip_known && (input.slip >= params.high_slip);
  const detail::LoadSum sum = detail::load_sum_of(load_sum);
  // Every pull is written before it is read: no zeroed array filled in.
  std::int32_t dp_raw[kWheelCount];
  std::uint32_t capped_mask = 0U;
  bool overflow = false;
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    // 0 <= load, 0 < ratio <= 2 (inputs_in_range).
    const auto load = static_cast<std::uint32_t>(loads.load_n[i].raw());
    const std::uint64_t fraction = saturated ? 0U : detail::load_fraction(load, sum);
    const detail::WheelPull pull = detail::wheel_pull(
        total, fraction, load, static_cast<std::uint32_t>(input.dp_max_ratio[i].raw()), saturated);
    dp_raw[i] = pull.dp_raw;
    capped_mask |= (pull.capped ? 1U : 0U) << i;
    overflow = overflow || pull.overflow;
  }
  if (overflow || !st.ok()) {
    return failed(DrawbarStatus::overflow);
  }
  DrawbarStatus status = DrawbarStatus::saturated;
  if (!saturated) {
    status = (capped_mask != 0U) ? DrawbarStatus::capped : DrawbarStatus::ok;
  }
  return DrawbarResult{{DrawbarPullN::from_raw(dp_raw[0]), DrawbarPullN::from_raw(dp_raw[1]),
                        DrawbarPullN::from_raw(dp_raw[2]), DrawbarPullN::from_raw(dp_raw[3]),
                        DrawbarPullN::from_raw(dp_raw[4]), DrawbarPullN::from_raw(dp_raw[5])},
                       total_n,
                       static_cast<std::uint8_t>(capped_mask),
                       status};
}

}  // namespace

DrawbarResult drawbar_pulls(const PreparedParameters& prepared, const WheelLoadResult& loads,
                            const DrawbarInput& input) noexcept {
  if (loads.status != WheelLoadStatus::ok) {
    return failed(DrawbarStatus::invalid_loads);
  }
  if (!prepared.ready()) {
    return failed(DrawbarStatus::invalid_input);
  }
  return pulls_of_valid(prepared.rover(), loads, input);
}

}  // namespace flight
}  // namespace sinkwatch

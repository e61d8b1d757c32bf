// Drawbar pull from the vehicle force balance; see drawbar_pull.hpp and
// docs/rover-loads.md, section 6. Twin: ground/reference/src/rover_loads.cpp.
#include "sinkwatch/flight/drawbar_pull.hpp"

#include "sinkwatch/fixedpoint/q.hpp"
#include "sinkwatch/fixedpoint/status.hpp"
#include "sinkwatch/fixedpoint/trig.hpp"
#include "sinkwatch/flight/constant_divisor.hpp"

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

/// W_i / sum W in Q31.32, bit for bit fx::div(W_i, sum W) of the loads
/// widened to Q31.32: both are whole multiples of 2^-16, so the quotient is
/// round(L_i 2^32 / S) of the raw Q15.16 integers L_i < 2^31 and S < 2^34,
/// whose 64-bit operands divide through one reciprocal of S per call
/// (constant_divisor.hpp) instead of six 128-bit long divisions. The
/// remainder scales with the quotient's operands, so the rounding is the same.
W load_fraction(WheelLoadN load, std::uint64_t load_sum, std::uint64_t load_sum_reciprocal) noexcept {
  const std::uint64_t n = static_cast<std::uint64_t>(load.raw()) << 32U;  // load >= 0 (inputs_in_range)
  // W_i <= sum W: the fraction is at most 1 (2^32 raw), well inside Q31.32.
  return W::from_raw(static_cast<std::int64_t>(rounded_quotient(n, load_sum, load_sum_reciprocal)));
}

/// The pulls for usable loads and parameters that passed
/// validate_rover_params().
DrawbarResult pulls_of_valid(const RoverParams& params, const WheelLoadResult& loads,
                             const DrawbarInput& input) noexcept {
  if (!inputs_in_range(params, loads, input)) {
    return failed(DrawbarStatus::invalid_input);
  }
  fx::Status st;
  // sum W in raw Q15.16 units: six values in [0, 2^31) sum below 2^34.
  std::uint64_t load_sum = 0U;
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    load_sum += static_cast<std::uint64_t>(loads.load_n[i].raw());
  }
  if (load_sum == 0U) {
    return failed(DrawbarStatus::invalid_loads);
  }
  const std::uint64_t load_sum_reciprocal = reciprocal_of(load_sum);

  // m (a + g sin(pitch)): the along-path force the tractions must supply.
  // The loads' sine when they were computed at this pitch (the step's case):
  // the same bits as computing it here.
  const fx::Q1_30 sin_pitch_q =
      (loads.pitch_rad == input.pitch_rad) ? loads.sin_pitch : fx::sin(input.pitch_rad.q(), st);
  const W sin_pitch = fx::rescale<W>(sin_pitch_q, st);
  const W g_along = fx::mul<W>(params.gravity_mps2.q(), sin_pitch, st);
  const W accel = fx::add(fx::rescale<W>(input.accel_mps2.q(), st), g_along, st);
  const W total = fx::mul<W>(params.mass_kg.q(), accel, st);

  DrawbarResult r{};
  r.total_n = DrawbarPullN{fx::rescale<LoadQ>(total, st)};
  const bool saturated = input.slip_known && (input.slip >= params.high_slip);
  for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
    const W load = fx::rescale<W>(loads.load_n[i].q(), st);
    const W cap = fx::mul<W>(input.dp_max_ratio[i].q(), load, st);
    W dp = cap;
    if (!saturated) {
      // total * (W_i / sum W): the fraction is in [0, 1], so the product
      // never exceeds |total|.
      const W share = fx::mul(total, load_fraction(loads.load_n[i], load_sum, load_sum_reciprocal), st);
      dp = fx::clamp(share, fx::neg(cap, st), cap, st);
      if (dp != share) {
        r.capped_mask = static_cast<std::uint8_t>(r.capped_mask | (1U << i));
      }
    }
    r.dp_n[i] = DrawbarPullN{fx::rescale<LoadQ>(dp, st)};
  }
  if (!st.ok()) {
    return failed(DrawbarStatus::overflow);
  }
  if (saturated) {
    r.status = DrawbarStatus::saturated;
  } else {
    r.status = (r.capped_mask != 0U) ? DrawbarStatus::capped : DrawbarStatus::ok;
  }
  return r;
}

}  // namespace

DrawbarResult drawbar_pulls(const RoverParams& params, const WheelLoadResult& loads,
                            const DrawbarInput& input) noexcept {
  if (loads.status != WheelLoadStatus::ok) {
    return failed(DrawbarStatus::invalid_loads);
  }
  if (validate_rover_params(params) != RoverParamStatus::ok) {
    return failed(DrawbarStatus::invalid_input);
  }
  return pulls_of_valid(params, loads, input);
}

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

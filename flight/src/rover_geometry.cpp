// RoverParams in the parameter table's section 6; see rover_geometry.hpp.
// Validation itself is in wheel_load.cpp next to the model it protects.
#include "sinkwatch/flight/rover_geometry.hpp"

namespace sinkwatch {
namespace flight {
namespace {

constexpr std::uint32_t kFieldCount = 19U;
static_assert((4U + (4U * kFieldCount)) == kRoverSectionBytes, "layout: header and 19 fields");
static_assert(kRoverSectionBytes <= kExtensionMaxBytes, "the section fits its frame");

/// The fields in section order, as raw int32 values.
void to_raw(const RoverParams& p, std::int32_t (&raw)[kFieldCount]) noexcept {
  const std::int32_t values[kFieldCount] = {
      p.mass_kg.raw(),         p.gravity_mps2.raw(),
      p.com_x_m.raw(),         p.com_y_m.raw(),
      p.com_z_m.raw(),         p.track_width_m.raw(),
      p.wheel_radius_m.raw(),  p.rocker_front_axle.x_m.raw(),
      p.rocker_front_axle.z_m.raw(), p.rocker_bogie_pivot.x_m.raw(),
      p.rocker_bogie_pivot.z_m.raw(), p.bogie_middle_axle.x_m.raw(),
      p.bogie_middle_axle.z_m.raw(),  p.bogie_rear_axle.x_m.raw(),
      p.bogie_rear_axle.z_m.raw(),    p.rocker_limit_rad.raw(),
      p.bogie_limit_rad.raw(),        p.attitude_limit_rad.raw(),
      p.high_slip.raw()};
  for (std::uint32_t i = 0U; i < kFieldCount; ++i) {
    raw[i] = values[i];
  }
}

RoverParams from_raw(const std::int32_t (&raw)[kFieldCount]) noexcept {
  RoverParams p{};
  p.mass_kg = MassKg::from_raw(raw[0]);
  p.gravity_mps2 = AccelMps2::from_raw(raw[1]);
  p.com_x_m = LengthM::from_raw(raw[2]);
  p.com_y_m = LengthM::from_raw(raw[3]);
  p.com_z_m = LengthM::from_raw(raw[4]);
  p.track_width_m = LengthM::from_raw(raw[5]);
  p.wheel_radius_m = LengthM::from_raw(raw[6]);
  p.rocker_front_axle = SidePointM{LengthM::from_raw(raw[7]), LengthM::from_raw(raw[8])};
  p.rocker_bogie_pivot = SidePointM{LengthM::from_raw(raw[9]), LengthM::from_raw(raw[10])};
  p.bogie_middle_axle = SidePointM{LengthM::from_raw(raw[11]), LengthM::from_raw(raw[12])};
  p.bogie_rear_axle = SidePointM{LengthM::from_raw(raw[13]), LengthM::from_raw(raw[14])};
  p.rocker_limit_rad = AngleRad::from_raw(raw[15]);
  p.bogie_limit_rad = AngleRad::from_raw(raw[16]);
  p.attitude_limit_rad = AngleRad::from_raw(raw[17]);
  p.high_slip = Ratio::from_raw(raw[18]);
  return p;
}

using SectionBytes = std::uint8_t[kExtensionMaxBytes];

// Byte access by index into the section's fixed-size array: every offset used
// below is a constant below kRoverSectionBytes <= kExtensionMaxBytes.
void put_u16(SectionBytes& out, std::uint32_t at, std::uint16_t v) noexcept {
  const std::uint32_t u = v;
  out[at] = static_cast<std::uint8_t>(u & 0xFFU);
  out[at + 1U] = static_cast<std::uint8_t>((u >> 8U) & 0xFFU);
}

std::uint16_t get_u16(const SectionBytes& in, std::uint32_t at) noexcept {
  const std::uint32_t lo = in[at];
  const std::uint32_t hi = in[at + 1U];
  return static_cast<std::uint16_t>(lo | (hi << 8U));
}

// Two's complement through uint32: int32 -> uint32 is modular (defined), and
// the way back subtracts 2^32 in int64, which is exact.
void put_i32(SectionBytes& out, std::uint32_t at, std::int32_t v) noexcept {
  const std::uint32_t u = static_cast<std::uint32_t>(v);
  for (std::uint32_t k = 0U; k < 4U; ++k) {
    out[at + k] = static_cast<std::uint8_t>((u >> (8U * k)) & 0xFFU);
  }
}

std::int32_t get_i32(const SectionBytes& in, std::uint32_t at) noexcept {
  std::uint32_t u = 0U;
  for (std::uint32_t k = 0U; k < 4U; ++k) {
    const std::uint32_t byte = in[at + k];
    u |= byte << (8U * k);
  }
  const std::int64_t wide = (u > 0x7FFFFFFFU) ? (static_cast<std::int64_t>(u) - 0x100000000LL)
                                              : static_cast<std::int64_t>(u);
  return static_cast<std::int32_t>(wide);
}

}  // namespace

void encode_rover_section(const RoverParams& params, ExtensionSection& out) noexcept {
  std::int32_t raw[kFieldCount]{};
  to_raw(params, raw);
  out.present = true;
  out.length = kRoverSectionBytes;
  put_u16(out.bytes, 0U, kRoverSectionLayout);
  put_u16(out.bytes, 2U, 0U);
  for (std::uint32_t i = 0U; i < kFieldCount; ++i) {
    put_i32(out.bytes, 4U + (4U * i), raw[i]);
  }
}

RoverParamStatus decode_rover_section(const ExtensionSection& section, RoverParams& out) noexcept {
  if (!section.present || (section.length != kRoverSectionBytes) ||
      (get_u16(section.bytes, 0U) != kRoverSectionLayout) || (get_u16(section.bytes, 2U) != 0U)) {
    return RoverParamStatus::bad_encoding;
  }
  std::int32_t raw[kFieldCount]{};
  for (std::uint32_t i = 0U; i < kFieldCount; ++i) {
    raw[i] = get_i32(section.bytes, 4U + (4U * i));
  }
  const RoverParams decoded = from_raw(raw);
  const RoverParamStatus status = validate_rover_params(decoded);
  if (status == RoverParamStatus::ok) {
    out = decoded;
  }
  return status;
}

bool rover_section_valid(const ExtensionSection& section) noexcept {
  RoverParams scratch{};
  return decode_rover_section(section, scratch) == RoverParamStatus::ok;
}

}  // namespace flight
}  // namespace sinkwatch

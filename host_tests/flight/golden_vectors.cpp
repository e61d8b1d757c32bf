#include "golden_vectors.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "prepared_support.hpp"
#include "sinkwatch/flight/correction.hpp"
#include "sinkwatch/flight/crc32.hpp"
#include "sinkwatch/flight/current_limit.hpp"
#include "sinkwatch/flight/estimator.hpp"
#include "sinkwatch/flight/motor.hpp"
#include "sinkwatch/flight/param_table.hpp"
#include "sinkwatch/flight/traction.hpp"

namespace sinkwatch {
namespace golden {

namespace {

using namespace sinkwatch::flight;

struct KindName {
  Kind kind;
  const char* name;
};
constexpr KindName kNames[] = {{Kind::sinkage, "sinkage"},         {Kind::pull, "pull"},
                               {Kind::torque, "torque"},           {Kind::current, "current"},
                               {Kind::corrections, "corrections"}, {Kind::limit, "limit"},
                               {Kind::table_crc, "table_crc"},     {Kind::resistance, "resistance"},
                               {Kind::ahead, "ahead"}};

std::int32_t i32(std::int64_t v) { return static_cast<std::int32_t>(v); }

Coefficients coeffs(const Row& r) {
  return Coefficients{Ratio::from_raw(i32(r.in[0])), Ratio::from_raw(i32(r.in[1])), Ratio::from_raw(i32(r.in[2]))};
}

MotorParams motor(const Row& r) {
  return MotorParams{GearRatio::from_raw(i32(r.in[0])), Efficiency::from_raw(i32(r.in[1])),
                     TorqueConstantNmPerA::from_raw(i32(r.in[2])), CurrentA::from_raw(i32(r.in[3])),
                     CurrentA::from_raw(i32(r.in[4]))};
}

DriveDirection direction(std::int64_t v) { return v == 0 ? DriveDirection::forward : DriveDirection::reverse; }

}  // namespace

const char* kind_name(Kind kind) {
  for (const KindName& k : kNames) {
    if (k.kind == kind) {
      return k.name;
    }
  }
  return "?";
}

bool kind_from_name(const char* name, Kind& kind) {
  for (const KindName& k : kNames) {
    if (std::strcmp(k.name, name) == 0) {
      kind = k.kind;
      return true;
    }
  }
  return false;
}

void evaluate(Row& r) {
  for (std::int64_t& o : r.out) {
    o = 0;
  }
  switch (r.kind) {
    case Kind::sinkage: {
      const SinkageResult z =
          sinkage_from_pull(coeffs(r), LengthM::from_raw(i32(r.in[3])), WheelLoadN::from_raw(i32(r.in[4])),
                            TorqueNm::from_raw(i32(r.in[5])), DrawbarPullN::from_raw(i32(r.in[6])));
      r.out[0] = z.sinkage_m.raw();
      r.status = static_cast<std::int64_t>(z.status);
      break;
    }
    case Kind::pull: {
      const DrawbarPullResult dp =
          pull_from_sinkage(coeffs(r), LengthM::from_raw(i32(r.in[3])), WheelLoadN::from_raw(i32(r.in[4])),
                            TorqueNm::from_raw(i32(r.in[5])), SinkageM::from_raw(i32(r.in[6])));
      r.out[0] = dp.drawbar_pull_n.raw();
      r.status = static_cast<std::int64_t>(dp.status);
      break;
    }
    case Kind::torque: {
      const TorqueResult t = torque_from_current(motor(r), CurrentA::from_raw(i32(r.in[5])), direction(r.in[6]));
      r.out[0] = t.torque_nm.raw();
      r.status = static_cast<std::int64_t>(t.status);
      break;
    }
    case Kind::current: {
      const CurrentResult i = test::current_of(motor(r), TorqueNm::from_raw(i32(r.in[5])), direction(r.in[6]));
      r.out[0] = i.current_a.raw();
      r.status = static_cast<std::int64_t>(i.status);
      break;
    }
    case Kind::corrections: {
      const ParameterTable table = default_parameter_table();
      const CorrectionResult c = test::corrections_of(table.correction, WheelLoadN::from_raw(i32(r.in[0])));
      r.out[0] = c.coefficients.c1.raw();
      r.out[1] = c.coefficients.c2.raw();
      r.out[2] = c.coefficients.c3.raw();
      r.out[3] = c.dp_max_ratio.raw();
      r.out[4] = static_cast<std::int64_t>(c.clamp);
      r.status = static_cast<std::int64_t>(c.status);
      break;
    }
    case Kind::limit: {
      const ParameterTable table = default_parameter_table();
      const CurrentLimitResult l =
          test::current_limit_of(table.correction, motor(r), LengthM::from_raw(i32(r.in[5])),
                        WheelLoadN::from_raw(i32(r.in[6])), SinkageM::from_raw(i32(r.in[7])));
      r.out[0] = l.current_limit_a.raw();
      r.out[1] = l.torque_limit_nm.raw();
      r.out[2] = static_cast<std::int64_t>(l.clamp);
      r.status = static_cast<std::int64_t>(l.status);
      break;
    }
    case Kind::table_crc: {
      std::uint8_t bytes[kMaxTableBytes];
      const EncodeResult e = encode(default_parameter_table(), bytes, sizeof bytes);
      // The CRC of the bytes before the trailer (the table's own CRC): the
      // CRC of all the bytes, trailer included, is CRC-32's constant residue
      // 0x2144DF1C whatever the table, and checked nothing.
      r.out[0] = ((e.status == RejectReason::ok) && (e.size >= kTableCrcBytes))
                     ? static_cast<std::int64_t>(crc32(bytes, e.size - kTableCrcBytes))
                     : 0;
      r.out[1] = static_cast<std::int64_t>(e.size);
      r.status = static_cast<std::int64_t>(e.status);
      break;
    }
    case Kind::resistance: {
      const ParameterTable table = default_parameter_table();
      TractionInput in{};
      in.loads_valid = true;
      for (std::uint32_t i = 0U; i < kWheelCount; ++i) {
        const std::uint32_t k = i % 3U;
        in.torque_valid[i] = true;
        in.torque_nm[i] = TorqueNm::from_raw(i32(r.in[1U + k]));
        in.drawbar_pull_n[i] = DrawbarPullN::from_raw(i32(r.in[4U + k]));
        in.load_n[i] = WheelLoadN::from_raw(i32(r.in[7U + k]));
        in.direction[i] = direction(r.in[10]);
      }
      TractionMonitor m;
      TractionOutput o{};
      m.step(in, table.traction, table.monitor, inverse_radius(LengthM::from_raw(i32(r.in[0]))), o);
      r.out[0] = o.rho_valid ? o.resistance.raw() : 0;
      r.status = static_cast<std::int64_t>(o.sample);
      break;
    }
    case Kind::ahead: {
      Ratio ahead{};
      const bool ok = carried_ahead(Ratio::from_raw(i32(r.in[0])), Ratio::from_raw(i32(r.in[1])), r.in[2],
                                    LengthM::from_raw(i32(r.in[3])), ahead);
      r.out[0] = ahead.raw();
      r.status = ok ? 0 : 1;
      break;
    }
    default:
      r.status = -1;
      break;
  }
}

Report check_flight_golden(const char* path) {
  Report rep{};
  rep.readable = false;
  std::FILE* f = std::fopen(path, "r");
  if (f == nullptr) {
    std::snprintf(rep.message, sizeof rep.message, "%.120s: cannot open", path);
    return rep;
  }
  rep.readable = true;
  char line[1024];
  int line_no = 0;
  bool header_seen = false;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    ++line_no;
    if (line[0] == '#' || line[0] == '\n' || line[0] == '\r') {
      continue;
    }
    if (!header_seen) {  // the column names
      header_seen = true;
      continue;
    }
    char* save = line;
    char* comma = std::strchr(save, ',');
    if (comma == nullptr) {
      rep.readable = false;
      std::snprintf(rep.message, sizeof rep.message, "%.120s:%d:1: expected kind,inputs,outputs,status", path, line_no);
      break;
    }
    *comma = '\0';
    Row expected{};
    if (!kind_from_name(save, expected.kind)) {
      rep.readable = false;
      std::snprintf(rep.message, sizeof rep.message, "%.120s:%d:1: unknown kind '%.40s'", path, line_no, save);
      break;
    }
    char* p = comma + 1;
    std::int64_t values[kInputs + kOutputs + 1];
    bool ok = true;
    for (int i = 0; i < kInputs + kOutputs + 1; ++i) {
      char* end = nullptr;
      values[i] = std::strtoll(p, &end, 10);
      if (end == p) {
        ok = false;
        std::snprintf(rep.message, sizeof rep.message, "%.120s:%d:%d: expected an integer in column %d", path, line_no,
                      static_cast<int>(p - line) + 1, i + 2);
        break;
      }
      p = end;
      if (*p == ',') {
        ++p;
      }
    }
    if (!ok) {
      rep.readable = false;
      break;
    }
    for (int i = 0; i < kInputs; ++i) {
      expected.in[i] = values[i];
    }
    for (int i = 0; i < kOutputs; ++i) {
      expected.out[i] = values[kInputs + i];
    }
    expected.status = values[kInputs + kOutputs];
    Row actual = expected;
    evaluate(actual);
    ++rep.rows;
    bool same = actual.status == expected.status;
    for (int i = 0; i < kOutputs; ++i) {
      same = same && (actual.out[i] == expected.out[i]);
    }
    if (!same) {
      ++rep.failures;
      if (rep.failures == 1) {
        rep.first_failure_line = line_no;
        std::snprintf(rep.message, sizeof rep.message,
                      "%.120s:%d: %s: expected out0=%lld status=%lld, got out0=%lld status=%lld", path, line_no,
                      kind_name(expected.kind), static_cast<long long>(expected.out[0]),
                      static_cast<long long>(expected.status), static_cast<long long>(actual.out[0]),
                      static_cast<long long>(actual.status));
      }
    }
  }
  std::fclose(f);
  return rep;
}

}  // namespace golden
}  // namespace sinkwatch

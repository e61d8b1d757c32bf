// make_flight_golden <out.csv>: writes the golden vectors of the flight
// functions (golden_vectors.hpp) from a fixed pseudo-random sequence, so the
// file is reproducible. Run it when the flight arithmetic changes on purpose,
// and review the diff of data/golden/flight_vectors.csv.
#include <cstdint>
#include <cstdio>

#include "golden_vectors.hpp"
#include "sinkwatch/fixedpoint/host_convert.hpp"
#include "sinkwatch/flight/units.hpp"

namespace {

using namespace sinkwatch;
using namespace sinkwatch::flight;

std::uint64_t g_state = 0x5EEDF11647ULL;
std::uint64_t next_u64() {  // splitmix64
  std::uint64_t z = (g_state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}
double uniform(double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(next_u64() >> 11) / 9007199254740992.0);
}
template <typename Qt>
std::int64_t raw(double v) {
  fx::Status st;
  return fx::from_double<Qt>(v, st).raw();
}

void emit(std::FILE* f, golden::Row row) {
  golden::evaluate(row);
  std::fprintf(f, "%s", golden::kind_name(row.kind));
  for (std::int64_t v : row.in) std::fprintf(f, ",%lld", static_cast<long long>(v));
  for (std::int64_t v : row.out) std::fprintf(f, ",%lld", static_cast<long long>(v));
  std::fprintf(f, ",%lld\n", static_cast<long long>(row.status));
}

golden::Row estimator_row(golden::Kind kind, double c1, double c2, double c3, double r, double w, double t,
                          double last) {
  golden::Row row{};
  row.kind = kind;
  row.in[0] = raw<RatioQ>(c1);
  row.in[1] = raw<RatioQ>(c2);
  row.in[2] = raw<RatioQ>(c3);
  row.in[3] = raw<LengthQ>(r);
  row.in[4] = raw<LoadQ>(w);
  row.in[5] = raw<LoadQ>(t);
  row.in[6] = kind == golden::Kind::sinkage ? raw<LoadQ>(last) : raw<LengthQ>(last);
  return row;
}

golden::Row motor_row(golden::Kind kind, double n, double eta, double kt, double i0, double imax) {
  golden::Row row{};
  row.kind = kind;
  row.in[0] = raw<GearQ>(n);
  row.in[1] = raw<EfficiencyQ>(eta);
  row.in[2] = raw<KtQ>(kt);
  row.in[3] = raw<CurrentQ>(i0);
  row.in[4] = raw<CurrentQ>(imax);
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <out.csv>\n", argv[0]);
    return 2;
  }
  std::FILE* f = std::fopen(argv[1], "w");
  if (f == nullptr) {
    std::fprintf(stderr, "%s: cannot open for writing\n", argv[1]);
    return 2;
  }
  std::fprintf(f,
               "# Golden vectors of the flight functions (issue 3): inputs as raw Q bits or enums, the flight\n"
               "# code's exact output bits and status. Written by host_tests/flight/make_flight_golden from a fixed\n"
               "# seed; checked by host_tests/flight (test_golden) and on ARM by flight_golden_check. Columns and\n"
               "# formats: host_tests/flight/golden_vectors.hpp.\n");
  std::fprintf(f, "kind");
  for (int i = 0; i < golden::kInputs; ++i) std::fprintf(f, ",in%d", i);
  for (int i = 0; i < golden::kOutputs; ++i) std::fprintf(f, ",out%d", i);
  std::fprintf(f, ",status\n");

  // Eq. 11 both ways over the valid envelope, then its edges.
  for (int i = 0; i < 150; ++i) {
    const double r = uniform(0.05, 0.5);
    const double w = uniform(5.0, 2000.0);
    const double t = uniform(-0.2, 1.0) * r * w;
    const double c1 = uniform(0.25, 4.0), c2 = uniform(0.25, 4.0), c3 = uniform(-1.0, 1.0);
    emit(f, estimator_row(golden::Kind::sinkage, c1, c2, c3, r, w, t, uniform(-0.2, 0.8) * w));
    emit(f, estimator_row(golden::Kind::pull, c1, c2, c3, r, w, t, uniform(0.0, 0.5) * r));
  }
  emit(f, estimator_row(golden::Kind::sinkage, 1, 1, 0.13, 0.15, 0.0, 1.0, 1.0));      // W = 0
  emit(f, estimator_row(golden::Kind::sinkage, 1, 1, 0.13, 0.0, 30.0, 1.0, 1.0));      // r = 0
  emit(f, estimator_row(golden::Kind::sinkage, 1, 0.0, 0.13, 0.15, 30.0, 1.0, 1.0));   // C2 = 0
  emit(f, estimator_row(golden::Kind::sinkage, 4, 0.25, -1, 2.0, 0.001, 30000, 1.0));  // overflow
  emit(f, estimator_row(golden::Kind::pull, 4, 1, 0.1, 0.01, 30.0, 30000, 0.01));      // overflow
  emit(f, estimator_row(golden::Kind::pull, 1, 1, 0.13, 2.5, 30.0, 1.0, 0.01));        // r too large

  // Motor model both ways.
  for (int i = 0; i < 100; ++i) {
    const double n = uniform(1.0, 2000.0), eta = uniform(0.1, 1.0), kt = uniform(0.001, 1.0);
    const double i0 = uniform(0.0, 0.5), imax = uniform(1.0, 50.0);
    golden::Row row = motor_row(golden::Kind::torque, n, eta, kt, i0, imax);
    row.in[5] = raw<CurrentQ>(uniform(-imax, imax));
    row.in[6] = static_cast<std::int64_t>(next_u64() & 1U);
    emit(f, row);
    golden::Row inv = motor_row(golden::Kind::current, n, eta, kt, i0, imax);
    inv.in[5] = raw<LoadQ>(uniform(-1.0, 1.0) * n * eta * kt * imax);
    inv.in[6] = static_cast<std::int64_t>(next_u64() & 1U);
    emit(f, inv);
  }
  golden::Row beyond = motor_row(golden::Kind::torque, 400, 0.6, 0.025, 0.1, 10.0);
  beyond.in[5] = raw<CurrentQ>(10.5);  // beyond the sensor
  emit(f, beyond);
  golden::Row bad_motor = motor_row(golden::Kind::torque, 400, 0.0, 0.025, 0.1, 10.0);
  bad_motor.in[5] = raw<CurrentQ>(1.0);
  emit(f, bad_motor);

  // Corrections over and beyond Table 2's loads.
  const double loads[] = {0.5, 10.0, 29.43, 30.0, 50.0, 68.67, 80.0, 98.1, 120.0, 147.15, 170.0, 196.2, 250.0, 2000.0};
  for (double w : loads) {
    golden::Row row{};
    row.kind = golden::Kind::corrections;
    row.in[0] = raw<LoadQ>(w);
    emit(f, row);
  }
  for (int i = 0; i < 30; ++i) {
    golden::Row row{};
    row.kind = golden::Kind::corrections;
    row.in[0] = raw<LoadQ>(uniform(1.0, 300.0));
    emit(f, row);
  }
  // Current limit (section 7).
  for (int i = 0; i < 60; ++i) {
    // One draw per statement: the order of evaluation of function arguments
    // is unspecified, and the file must be the same on every compiler.
    const double n = uniform(50, 1000);
    const double eta = uniform(0.3, 1.0);
    const double kt = uniform(0.005, 0.1);
    const double i0 = uniform(0.0, 0.3);
    golden::Row row = motor_row(golden::Kind::limit, n, eta, kt, i0, 20.0);
    row.in[5] = raw<LengthQ>(uniform(0.05, 0.4));
    row.in[6] = raw<LoadQ>(uniform(5.0, 400.0));
    row.in[7] = raw<LengthQ>(uniform(0.005, 0.1));
    emit(f, row);
  }
  golden::Row table{};
  table.kind = golden::Kind::table_crc;
  emit(f, table);
  // The motion-resistance coefficient and the trend carried ahead
  // (traction.hpp): 64-bit integer arithmetic, the same bits on every target.
  for (int i = 0; i < 60; ++i) {
    golden::Row row{};
    row.kind = golden::Kind::resistance;
    row.in[0] = raw<LengthQ>(uniform(0.01, 2.0));
    for (int k = 0; k < 3; ++k) row.in[1 + k] = raw<LoadQ>(uniform(-200.0, 200.0));
    for (int k = 0; k < 3; ++k) row.in[4 + k] = raw<LoadQ>(uniform(-500.0, 500.0));
    for (int k = 0; k < 3; ++k) row.in[7 + k] = raw<LoadQ>(uniform(1.0, 3000.0));
    row.in[10] = static_cast<std::int64_t>(next_u64() & 1U);
    emit(f, row);
  }
  golden::Row huge{};  // the torque sum beyond 32768 N m: overflow
  huge.kind = golden::Kind::resistance;
  huge.in[0] = raw<LengthQ>(0.15);
  for (int k = 0; k < 3; ++k) huge.in[1 + k] = raw<LoadQ>(6000.0);
  for (int k = 0; k < 3; ++k) huge.in[7 + k] = raw<LoadQ>(20000.0);
  emit(f, huge);
  for (int i = 0; i < 40; ++i) {
    golden::Row row{};
    row.kind = golden::Kind::ahead;
    row.in[0] = raw<RatioQ>(uniform(-1.0, 4.0));
    row.in[1] = raw<RatioQ>(uniform(-1.0, 4.0));
    row.in[2] = raw<LengthQ>(uniform(0.2, 10.0));
    row.in[3] = raw<LengthQ>(uniform(0.0, 10.0));
    emit(f, row);
  }
  std::fclose(f);
  return 0;
}

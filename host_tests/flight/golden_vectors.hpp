// golden_vectors.hpp: bit-exact vectors of the flight functions.
//
// data/golden/flight_vectors.csv holds one computation per row: the function
// (kind), up to 12 integer inputs (raw Q bits or enums) and the exact output
// bits and status the flight code produced when the file was made
// (make_flight_golden). check_flight_golden() recomputes every row and
// compares bit for bit. It uses only <cstdio> and the flight library, so the
// firmware build can run the same check on 32-bit ARM under qemu
// (flight_golden_check <path>).
//
// Row format (CSV, '#' lines are comments):
//   kind,in0,...,in11,out0,...,out4,status
// kinds and their columns:
//   sinkage      c1 c2 c3 r W T DP            -> z
//   pull         c1 c2 c3 r W T z             -> DP
//   torque       N eta Kt I0 Imax I dir       -> T
//   current      N eta Kt I0 Imax T dir       -> I
//   corrections  W (default table)           -> c1 c2 c3 dp_max/W clamp
//   limit        N eta Kt I0 Imax r W z_max (default corrections) -> I_max T_max clamp
//   table_crc    (none)                       -> the encoded default table's CRC-32 (its trailer), its size
//   resistance   r T0 T1 T2 DP0 DP1 DP2 W0 W1 W2 dir (wheels 3..5 repeat 0..2; default table's
//                section 4 and 8, traction.hpp)      -> rho (0 without a number); status: TractionSample
//   ahead        rho_med rho_back distance(raw LengthM sum) lookahead -> rho_ahead; status 0 ok, 1 overflow
#ifndef SINKWATCH_HOST_TESTS_FLIGHT_GOLDEN_VECTORS_HPP
#define SINKWATCH_HOST_TESTS_FLIGHT_GOLDEN_VECTORS_HPP

#include <cstdint>

namespace sinkwatch {
namespace golden {

constexpr int kInputs = 12;
constexpr int kOutputs = 5;

enum class Kind : std::uint8_t { sinkage, pull, torque, current, corrections, limit, table_crc, resistance, ahead };

struct Row {
  Kind kind;
  std::int64_t in[kInputs];
  std::int64_t out[kOutputs];
  std::int64_t status;
};

const char* kind_name(Kind kind);
bool kind_from_name(const char* name, Kind& kind);

/// Runs the flight function of row.kind on row.in and fills out and status.
void evaluate(Row& row);

struct Report {
  int rows;              ///< rows checked
  int failures;          ///< rows whose bits differ
  int first_failure_line;
  char message[512];     ///< what differed first, or why the file could not be read
  bool readable;
};

/// Checks every row of the file at `path`.
Report check_flight_golden(const char* path);

}  // namespace golden
}  // namespace sinkwatch

#endif

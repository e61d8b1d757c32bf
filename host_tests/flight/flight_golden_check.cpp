// flight_golden_check <path>: checks data/golden/flight_vectors.csv bit for
// bit; exit 0 when every row matches. Built for the host here and for ARM by
// the firmware build (run under qemu).
#include <cstdio>

#include "golden_vectors.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <flight_vectors.csv>\n", argv[0]);
    return 2;
  }
  const sinkwatch::golden::Report r = sinkwatch::golden::check_flight_golden(argv[1]);
  if (!r.readable) {
    std::fprintf(stderr, "%s\n", r.message);
    return 2;
  }
  std::printf("%d rows, %d differ\n", r.rows, r.failures);
  if (r.failures != 0) {
    std::fprintf(stderr, "%s\n", r.message);
    return 1;
  }
  return r.rows > 0 ? 0 : 1;
}

// Benchmark of `sinkwatch campaign` (docs/campaign.md, "Speed"): runs a
// campaign of every family (default 2 traverses each, argv[1] to change) on
// all cores and prints traverses per second and the projected time of 500
// traverses. Not a test: it prints numbers.
#include "sinkwatch/ground/campaign.hpp"

#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <thread>

int main(int argc, char** argv) {
  using namespace sinkwatch::ground;
  CampaignOptions options;
  options.traverses_per_family = argc > 1 ? static_cast<std::size_t>(std::strtoul(argv[1], nullptr, 10)) : 2U;
  options.threads = argc > 2 ? static_cast<unsigned>(std::strtoul(argv[2], nullptr, 10)) : 0U;
  const CampaignResult r = run_campaign(options);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double cpu_s = static_cast<double>(usage.ru_utime.tv_sec) + 1e-6 * static_cast<double>(usage.ru_utime.tv_usec);
  std::size_t rows = 0;
  for (const TraverseResult& t : r.traverses) rows += t.rows;
  const double n = static_cast<double>(r.traverses.size());
  const unsigned threads = options.threads != 0 ? options.threads : std::thread::hardware_concurrency();
  std::printf("campaign: %zu traverses (%zu per family, path %.0f m), %zu simulated cycles, %u threads\n",
              r.traverses.size(), options.traverses_per_family, options.path_length_m, rows, threads);
  std::printf("  wall %.1f s: %.3f traverses/s, %.0f cycles/s\n", r.seconds, n / r.seconds,
              static_cast<double>(rows) / r.seconds);
  std::printf("  projection: 500 traverses in %.0f s (%.1f min) at this wall rate; aim < 10 min\n",
              500.0 * r.seconds / n, 500.0 * r.seconds / n / 60.0);
  // On a shared machine the wall time includes other processes' load; the
  // CPU time does not: 500 traverses on `threads` otherwise idle cores.
  std::printf("  cpu %.1f s (%.2f s per traverse): 500 traverses on %u idle cores in %.0f s (%.1f min)\n", cpu_s,
              cpu_s / n, threads, 500.0 * cpu_s / n / threads, 500.0 * cpu_s / n / threads / 60.0);
  return 0;
}

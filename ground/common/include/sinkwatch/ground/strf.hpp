// strf.hpp: printf-style formatting into a std::string, for the ground
// tools' reports (one helper instead of a copy per report).
#ifndef SINKWATCH_GROUND_STRF_HPP
#define SINKWATCH_GROUND_STRF_HPP

#include <cstdarg>
#include <cstdio>
#include <string>

namespace sinkwatch {
namespace ground {

/// The formatted text, cut at 511 characters (report lines, not documents).
inline std::string strf(const char* format, ...) __attribute__((format(printf, 1, 2)));
inline std::string strf(const char* format, ...) {
  char buf[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buf, sizeof buf, format, args);
  va_end(args);
  return buf;
}

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_STRF_HPP

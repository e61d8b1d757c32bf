// Helpers for the input-rule tests of both CSV readers (docs/input-files.md):
// the soil-bin reader's (host_tests/calib) and the telemetry reader's
// (host_tests/replay) tests feed standard input and check what a message may
// send to a terminal in the same way.
#pragma once

#include <iostream>
#include <sstream>
#include <string>

namespace sinkwatch::test {

// Redirects std::cin to `text` for the lifetime of the object.
class StdinFrom {
 public:
  explicit StdinFrom(const std::string& text) : in_(text), old_(std::cin.rdbuf(in_.rdbuf())) {}
  ~StdinFrom() {
    std::cin.rdbuf(old_);
    std::cin.clear();
  }
  StdinFrom(const StdinFrom&) = delete;
  StdinFrom& operator=(const StdinFrom&) = delete;

 private:
  std::istringstream in_;
  std::streambuf* old_;
};

// True when every byte of `text` is printable ASCII (what a message may send
// to a terminal).
inline bool printable_ascii(const std::string& text) {
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20U || byte >= 0x7FU) {
      return false;
    }
  }
  return true;
}

}  // namespace sinkwatch::test

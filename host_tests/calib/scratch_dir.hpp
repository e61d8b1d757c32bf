// scratch_dir.hpp: a fresh, empty directory per test, under one directory per
// process (the process id keeps concurrent runs of two build trees apart),
// removed when the process ends. Shared by the calibration tests that write
// files.
#ifndef SINKWATCH_HOST_TESTS_CALIB_SCRATCH_DIR_HPP
#define SINKWATCH_HOST_TESTS_CALIB_SCRATCH_DIR_HPP

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace sinkwatch {
namespace test {

struct ScratchRoot {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("sinkwatch_calib_tests_" + std::to_string(::getpid()));
  ~ScratchRoot() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

inline ScratchRoot& scratch_root() {
  static ScratchRoot root;
  return root;
}

/// A fresh, empty directory named after the running test.
inline std::filesystem::path scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      scratch_root().path / (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace test
}  // namespace sinkwatch

#endif  // SINKWATCH_HOST_TESTS_CALIB_SCRATCH_DIR_HPP

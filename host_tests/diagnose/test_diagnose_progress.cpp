// The progress bar of `sinkwatch diagnose` (issue 16): drawn on standard
// error only when it is a terminal and -q is not given; nothing otherwise.
// The terminal is a pseudo-terminal from util-linux `script`; without it the
// terminal cases are skipped.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

const std::string kRun = std::string("'") + SINKWATCH_CLI + "' diagnose --real '" + SINKWATCH_DATA_DIR +
                         "/paper/table1_3kg.csv' --model estimator --radius 0.15 --width 0.15";

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

fs::path scratch() {
  const fs::path dir = fs::temp_directory_path() / ("sinkwatch_progress_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

// Standard error of `command` run with a pseudo-terminal as its terminal
// (`script` copies what the terminal shows, standard output sent elsewhere).
std::string terminal_stderr(const std::string& command) {
  const fs::path out = scratch() / "terminal.txt";
  const std::string run = "script -qec \"" + command + " >/dev/null\" /dev/null >'" + out.string() + "' 2>&1";
  EXPECT_EQ(std::system(run.c_str()), 0) << run;
  return slurp(out);
}

bool have_script() { return std::system("command -v script >/dev/null 2>&1") == 0; }

TEST(DiagnoseProgress, NothingOnStandardErrorWhenItIsNotATerminal) {
  const fs::path err = scratch() / "stderr.txt";
  const std::string run = kRun + " >/dev/null 2>'" + err.string() + "'";
  ASSERT_EQ(std::system(run.c_str()), 0) << run;
  EXPECT_EQ(slurp(err), "");
}

TEST(DiagnoseProgress, ABarOnATerminal) {
  if (!have_script()) {
    GTEST_SKIP() << "no `script` to make a terminal";
  }
  const std::string shown = terminal_stderr(kRun);
  EXPECT_NE(shown.find("candidate fits"), std::string::npos) << shown;
  EXPECT_NE(shown.find("] 4/4 candidate fits"), std::string::npos) << shown;
}

TEST(DiagnoseProgress, NothingOnATerminalUnderQuiet) {
  if (!have_script()) {
    GTEST_SKIP() << "no `script` to make a terminal";
  }
  EXPECT_EQ(terminal_stderr(kRun + " -q"), "");
}

}  // namespace

// The output module of the ground tools (output_file.hpp,
// docs/output-files.md): what an output may replace, the temporary-then-
// rename write with every error checked, several outputs as one set, and
// standard output; then the built executable on the defects of issue 17
// (a symlink replaced by a file, /dev/full as standard output, a FIFO target,
// a missing directory found only after the run).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "scratch_dir.hpp"
#include "sinkwatch/ground/output_file.hpp"

namespace sinkwatch {
namespace ground {
namespace {

namespace fs = std::filesystem;
using sinkwatch::test::scratch_dir;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void put(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// The names in `dir`, hidden ones (the temporaries) included.
std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

// The message of the OutputError `f` throws ("" when it throws none).
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const OutputError& e) {
    return e.what();
  }
  return "";
}

// While alive, a file this process writes cannot grow beyond `bytes`: a
// write past it fails with EFBIG (SIGXFSZ ignored), as a full disk would.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    old_handler_ = ::signal(SIGXFSZ, SIG_IGN);
    ::getrlimit(RLIMIT_FSIZE, &old_);
    rlimit limit = old_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &old_);
    ::signal(SIGXFSZ, old_handler_);
  }

 private:
  rlimit old_{};
  sighandler_t old_handler_;
};

TEST(OutputFile, WritesANewFileThroughATemporaryAndLeavesNothingElse) {
  const fs::path dir = scratch_dir();
  write_output_file((dir / "out.txt").string(), "hello\n");
  EXPECT_EQ(slurp(dir / "out.txt"), "hello\n");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"out.txt"});
  // A new file gets 0666 less the umask, not mkstemp's 0600.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  EXPECT_EQ(fs::status(dir / "out.txt").permissions(), static_cast<fs::perms>(0666 & ~mask));
}

TEST(OutputFile, ReplacesARegularFileKeepingItsMode) {
  const fs::path dir = scratch_dir();
  put(dir / "out.txt", "old content that is longer\n");
  fs::permissions(dir / "out.txt", static_cast<fs::perms>(0640));
  write_output_file((dir / "out.txt").string(), "new\n");
  EXPECT_EQ(slurp(dir / "out.txt"), "new\n");
  EXPECT_EQ(fs::status(dir / "out.txt").permissions(), static_cast<fs::perms>(0640));
}

TEST(OutputFile, ASymlinkStaysASymlinkAndItsTargetIsWritten) {
  const fs::path dir = scratch_dir();
  fs::create_directories(dir / "data");
  put(dir / "data" / "real.csv", "old\n");
  fs::create_symlink("data/real.csv", dir / "link.csv");
  EXPECT_EQ(check_output_path((dir / "link.csv").string()), fs::canonical(dir / "data" / "real.csv").string());
  write_output_file((dir / "link.csv").string(), "new\n");
  EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
  EXPECT_EQ(fs::read_symlink(dir / "link.csv"), fs::path("data/real.csv"));
  EXPECT_EQ(slurp(dir / "data" / "real.csv"), "new\n");
  // The temporary was made beside the file the link points to, and is gone.
  EXPECT_EQ(names_in(dir / "data"), std::vector<std::string>{"real.csv"});
  EXPECT_EQ(names_in(dir), (std::vector<std::string>{"data", "link.csv"}));
}

TEST(OutputFile, ADanglingSymlinkIsRefused) {
  const fs::path dir = scratch_dir();
  fs::create_symlink("nowhere.csv", dir / "link.csv");
  const std::string message = error_of([&] { write_output_file((dir / "link.csv").string(), "x"); });
  EXPECT_NE(message.find((dir / "link.csv").string() + ": "), std::string::npos) << message;
  EXPECT_NE(message.find("symbolic link"), std::string::npos) << message;
  EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"link.csv"});
}

TEST(OutputFile, ADeviceIsRefusedAndNeverReplaced) {
  // check_output_path only: the write is refused by the same check, and
  // this test must not risk /dev/full itself if it ever failed.
  const std::string message = error_of([] { (void)check_output_path("/dev/full"); });
  EXPECT_EQ(message, "/dev/full: refusing to replace a character device; outputs replace only regular files");
  EXPECT_NE(error_of([] { (void)check_output_path("/dev/null"); }), "");
}

TEST(OutputFile, ASymlinkToADeviceIsRefused) {
  const fs::path dir = scratch_dir();
  fs::create_symlink("/dev/full", dir / "full");
  const std::string message = error_of([&] { (void)check_output_path((dir / "full").string()); });
  EXPECT_NE(message.find("character device"), std::string::npos) << message;
  EXPECT_NE(message.find("/dev/full"), std::string::npos) << message;
}

TEST(OutputFile, ADirectoryFifoOrSocketIsRefused) {
  const fs::path dir = scratch_dir();
  fs::create_directories(dir / "sub");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  const int sock = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(sock, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::string socket_path = (dir / "sock").string();
  const bool bound = socket_path.size() < sizeof address.sun_path &&
                     (std::strcpy(address.sun_path, socket_path.c_str()),
                      ::bind(sock, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0);

  EXPECT_NE(error_of([&] { write_output_file((dir / "sub").string(), "x"); }).find("a directory"), std::string::npos);
  EXPECT_NE(error_of([&] { write_output_file((dir / "fifo").string(), "x"); }).find("a FIFO"), std::string::npos);
  EXPECT_TRUE(fs::is_directory(dir / "sub"));
  EXPECT_TRUE(fs::is_fifo(dir / "fifo"));
  if (bound) {
    EXPECT_NE(error_of([&] { write_output_file(socket_path, "x"); }).find("a socket"), std::string::npos);
    EXPECT_TRUE(fs::is_socket(dir / "sock"));
  }
  ::close(sock);
}

TEST(OutputFile, AMissingOrUnwritableDirectoryIsRefusedUpFront) {
  const fs::path dir = scratch_dir();
  std::string message = error_of([] { (void)check_output_path("/nonexistent/x.json"); });
  EXPECT_EQ(message, "/nonexistent/x.json: cannot write here: directory /nonexistent: " +
                         std::string(std::strerror(ENOENT)));
  // A file where a directory should be.
  put(dir / "plain", "x");
  message = error_of([&] { (void)check_output_path((dir / "plain" / "x.json").string()); });
  EXPECT_NE(message.find((dir / "plain" / "x.json").string() + ": "), std::string::npos) << message;
  // The constructor checks too, before creating anything.
  EXPECT_NE(error_of([] { OutputFile f("/nonexistent/x.json"); }), "");
  if (::geteuid() != 0) {  // root may write anywhere
    fs::create_directories(dir / "ro");
    fs::permissions(dir / "ro", static_cast<fs::perms>(0555));
    message = error_of([&] { (void)check_output_path((dir / "ro" / "x.json").string()); });
    EXPECT_NE(message.find(std::strerror(EACCES)), std::string::npos) << message;
    fs::permissions(dir / "ro", static_cast<fs::perms>(0755));
  }
  EXPECT_NE(error_of([] { (void)check_output_path(""); }), "");
}

TEST(OutputFile, AWriteErrorLeavesTheOldContentAndNoTemporary) {
  const fs::path dir = scratch_dir();
  put(dir / "out.csv", "old\n");
  const std::string big(1 << 20, 'x');
  std::string message;
  {
    FileSizeLimit limit(4096);  // the write fails part-way, like a full disk
    message = error_of([&] { write_output_file((dir / "out.csv").string(), big); });
  }
  EXPECT_EQ(message, (dir / "out.csv").string() + ": write failed: " + std::strerror(EFBIG));
  EXPECT_EQ(slurp(dir / "out.csv"), "old\n");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"out.csv"});
}

TEST(OutputFile, AWriteErrorThroughTheStreamIsFoundAtCommit) {
  const fs::path dir = scratch_dir();
  put(dir / "out.csv", "old\n");
  std::string message;
  {
    FileSizeLimit limit(4096);
    message = error_of([&] {
      OutputFile file((dir / "out.csv").string());
      for (int i = 0; i < 100000; ++i) file.stream() << "row " << i << '\n';
      file.commit();
    });
  }
  EXPECT_NE(message.find(std::strerror(EFBIG)), std::string::npos) << message;
  EXPECT_EQ(slurp(dir / "out.csv"), "old\n");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"out.csv"});
}

TEST(OutputFile, AnExceptionBeforeCommitRemovesTheTemporary) {
  const fs::path dir = scratch_dir();
  put(dir / "out.csv", "old\n");
  try {
    OutputFile file((dir / "out.csv").string());
    file.write("half of it");
    throw std::runtime_error("the computation failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(slurp(dir / "out.csv"), "old\n");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"out.csv"});
}

TEST(OutputFileSet, AnErrorInOneLeavesEveryTargetUntouched) {
  const fs::path dir = scratch_dir();
  put(dir / "a.json", "old a\n");
  put(dir / "b.bin", "old b\n");
  std::string message;
  {
    FileSizeLimit limit(4096);
    message = error_of([&] {
      OutputFileSet set;
      set.add((dir / "a.json").string()).write("new a\n");
      set.add((dir / "b.bin").string()).write(std::string(1 << 20, 'b'));
      set.commit();
    });
  }
  EXPECT_NE(message.find((dir / "b.bin").string()), std::string::npos) << message;
  EXPECT_EQ(slurp(dir / "a.json"), "old a\n");
  EXPECT_EQ(slurp(dir / "b.bin"), "old b\n");
  EXPECT_EQ(names_in(dir), (std::vector<std::string>{"a.json", "b.bin"}));
}

TEST(OutputFileSet, AnImageAnotherProgramDidNotWriteLeavesEveryTargetUntouched) {
  // As a gnuplot run that exits 0 without drawing: the set's text file must
  // not be renamed into place either.
  const fs::path dir = scratch_dir();
  put(dir / "summary.md", "old\n");
  const std::string message = error_of([&] {
    OutputFileSet set;
    set.add((dir / "summary.md").string()).write("new\n");
    OutputFile& image = set.add((dir / "plot.svg").string());
    image.close();  // handed to the other program, which writes nothing
    set.commit();
  });
  EXPECT_NE(message.find((dir / "plot.svg").string() + ": the output is empty"), std::string::npos) << message;
  EXPECT_EQ(slurp(dir / "summary.md"), "old\n");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"summary.md"});
}

TEST(OutputFile, AnImageAnotherProgramWroteIsRenamedIntoPlace) {
  const fs::path dir = scratch_dir();
  OutputFile image((dir / "plot.svg").string());
  image.close();
  EXPECT_EQ(fs::path(image.temporary_path()).extension(), ".svg") << "gnuplot terminals go by the extension";
  put(image.temporary_path(), "<svg/>");
  image.commit();
  EXPECT_EQ(slurp(dir / "plot.svg"), "<svg/>");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"plot.svg"});
}

TEST(OutputFileSet, WritesAllAndRefusesOneTargetTwice) {
  const fs::path dir = scratch_dir();
  {
    OutputFileSet set;
    set.add((dir / "a").string()).write("1");
    set.add((dir / "b").string()).write("2");
    set.commit();
  }
  EXPECT_EQ(slurp(dir / "a"), "1");
  EXPECT_EQ(slurp(dir / "b"), "2");
  fs::create_symlink("a", dir / "also_a");
  OutputFileSet set;
  set.add((dir / "a").string());
  EXPECT_NE(error_of([&] { set.add((dir / "also_a").string()); }).find("the same file"), std::string::npos);
}

TEST(StandardOutput, DashWritesToTheGivenStream) {
  std::ostringstream out;
  EXPECT_EQ(check_output_path("-"), "-");
  write_output_file("-", "to stdout\n", &out);
  EXPECT_EQ(out.str(), "to stdout\n");
}

TEST(StandardOutput, AFullDeviceIsAnErrorAtTheEnd) {
  std::ofstream full("/dev/full");
  ASSERT_TRUE(full.is_open());
  std::string message = error_of([&] {
    OutputFile file("-", &full);
    file.stream() << "a line\n";
    file.commit();
  });
  EXPECT_EQ(message.rfind("standard output: write failed", 0), 0U) << message;
  std::ofstream full_again("/dev/full");
  full_again << std::string(100000, 'x');
  message = error_of([&] { finish_standard_output(full_again); });
  EXPECT_EQ(message.rfind("standard output: write failed", 0), 0U) << message;
}

TEST(OutputDirectory, ChecksTheDirectoryOrItsParent) {
  const fs::path dir = scratch_dir();
  check_output_directory(dir.string());
  check_output_directory((dir / "new").string());  // the parent exists
  EXPECT_FALSE(fs::exists(dir / "new"));
  EXPECT_NE(error_of([&] { check_output_directory((dir / "new" / "deeper").string()); }), "");
  EXPECT_NE(error_of([] { check_output_directory("/nonexistent/report"); }).find("/nonexistent/report: "),
            std::string::npos);
  put(dir / "file", "x");
  EXPECT_NE(error_of([&] { check_output_directory((dir / "file").string()); }).find("not a directory"),
            std::string::npos);
  create_output_directory((dir / "new").string());
  EXPECT_TRUE(fs::is_directory(dir / "new"));
}

// ---- the executable -------------------------------------------------------

const std::string kTable1 = std::string(SINKWATCH_DATA_DIR) + "/paper/table1_3kg.csv";

struct CliRun {
  int exit_code;
  std::string out;
  std::string err;
};

// Runs `sinkwatch ARGUMENTS` with standard output to `stdout_to` (a file in
// `dir` by default) and standard error to a file in `dir`.
CliRun run_cli(const std::string& arguments, const fs::path& dir, const std::string& stdout_to = "") {
  const fs::path out = dir / "stdout.txt";
  const fs::path err = dir / "stderr.txt";
  const std::string command = std::string("'") + SINKWATCH_CLI + "' " + arguments + " >'" +
                              (stdout_to.empty() ? out.string() : stdout_to) + "' 2>'" + err.string() + "'";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, stdout_to.empty() ? slurp(out) : std::string(),
          slurp(err)};
}

TEST(OutputCli, SimulateToAFullStandardOutputFails) {
  const fs::path dir = scratch_dir();
  const CliRun run = run_cli("simulate", dir, "/dev/full");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("sinkwatch simulate: standard output: write failed"), std::string::npos) << run.err;
}

TEST(OutputCli, CalibrateReportToAFullStandardOutputFailsAndWritesNoFile) {
  const fs::path dir = scratch_dir();
  const CliRun run = run_cli("calibrate '" + kTable1 + "' --json '" + (dir / "fit.json").string() + "'", dir,
                             "/dev/full");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("standard output"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir / "fit.json")) << "the files are renamed only after the report is out";
}

TEST(OutputCli, SimulateThroughASymlinkKeepsTheLink) {
  const fs::path dir = scratch_dir();
  put(dir / "real.csv", "old\n");
  fs::create_symlink("real.csv", dir / "link.csv");
  const CliRun run = run_cli("simulate --out '" + (dir / "link.csv").string() + "'", dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
  EXPECT_EQ(slurp(dir / "real.csv").rfind("# sinkwatch simulate", 0), 0U);
}

TEST(OutputCli, CalibrateThroughASymlinkKeepsTheLink) {
  // The old write-then-rename replaced the link by a file.
  const fs::path dir = scratch_dir();
  fs::create_directories(dir / "runs");
  put(dir / "runs" / "run-42.json", "old\n");
  fs::create_symlink("runs/run-42.json", dir / "latest.json");
  const CliRun run = run_cli("calibrate '" + kTable1 + "' --json '" + (dir / "latest.json").string() + "'", dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(fs::is_symlink(dir / "latest.json"));
  EXPECT_NE(slurp(dir / "runs" / "run-42.json").find("\"c1\""), std::string::npos);
  EXPECT_EQ(names_in(dir / "runs"), std::vector<std::string>{"run-42.json"});
}

TEST(OutputCli, CalibrateRefusesAFifoAndADirectoryAndLeavesThem) {
  const fs::path dir = scratch_dir();
  ASSERT_EQ(::mkfifo((dir / "fit.json").c_str(), 0600), 0);
  fs::create_directories(dir / "table.bin");
  CliRun run = run_cli("calibrate '" + kTable1 + "' --json '" + (dir / "fit.json").string() + "'", dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find((dir / "fit.json").string() + ": refusing to replace a FIFO"), std::string::npos)
      << run.err;
  EXPECT_TRUE(fs::is_fifo(dir / "fit.json"));
  EXPECT_EQ(run.out, "") << "refused before the fit";
  run = run_cli("calibrate '" + kTable1 + "' --load 29.43 --table '" + (dir / "table.bin").string() + "'", dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("refusing to replace a directory"), std::string::npos) << run.err;
  EXPECT_TRUE(fs::is_directory(dir / "table.bin"));
  EXPECT_EQ(run.out, "");
}

TEST(OutputCli, CalibrateToAMissingDirectoryFailsBeforeTheFit) {
  const fs::path dir = scratch_dir();
  const CliRun run = run_cli("calibrate '" + kTable1 + "' --json /nonexistent/x.json", dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("/nonexistent/x.json: cannot write here"), std::string::npos) << run.err;
  EXPECT_EQ(run.out, "") << "no report: the path was checked before the fit";
}

TEST(OutputCli, CalibrateToStandardOutputWithDash) {
  const fs::path dir = scratch_dir();
  const CliRun run = run_cli("calibrate '" + kTable1 + "' --json -", dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("\"c1\""), std::string::npos);
  EXPECT_FALSE(fs::exists(fs::current_path() / "-")) << "- is standard output, not a file";
}

}  // namespace
}  // namespace ground
}  // namespace sinkwatch

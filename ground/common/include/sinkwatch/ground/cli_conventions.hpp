// cli_conventions.hpp: the one command-line convention of every `sinkwatch`
// subcommand (docs/conventions.md): exit codes, the "sinkwatch <tool>: "
// prefix of every error message, -q/--quiet and -v/--verbose, validators for
// numeric options, and the top-level parse that turns CLI11's own errors into
// usage errors.
#ifndef SINKWATCH_GROUND_CLI_CONVENTIONS_HPP
#define SINKWATCH_GROUND_CLI_CONVENTIONS_HPP

#include <CLI/CLI.hpp>

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace sinkwatch {
namespace ground {

/// The exit status of every subcommand.
enum class ExitCode : int {
  ok = 0,           // done (also --help and --version)
  data_error = 1,   // an input could not be read or is malformed, an output could not be written,
                    // or the computation failed on the given data
  usage_error = 2,  // the command line is wrong: unknown option, bad value, conflicting options
};

/// The process exit status of `code`.
constexpr int exit_status(ExitCode code) noexcept { return static_cast<int>(code); }

/// "sinkwatch <tool>: ", or "sinkwatch: " when `tool` is empty. Every error
/// message starts with it.
std::string error_prefix(const std::string& tool);

/// What a subcommand prints on stderr besides its errors.
struct Verbosity {
  bool quiet = false;    // -q/--quiet: errors only
  bool verbose = false;  // -v/--verbose: extra detail
  /// Informational messages (progress, notes, warnings) are printed unless quiet.
  [[nodiscard]] bool inform() const noexcept { return !quiet; }
};

/// Adds -q/--quiet and -v/--verbose (which exclude each other) to `sub`,
/// stored in `verbosity` (which must outlive the parse).
void add_verbosity_flags(CLI::App& sub, Verbosity& verbosity);

/// A finite number (no nan or inf).
CLI::Validator finite_number();
/// A finite number > 0; `unit` (e.g. "m") is named in the message and help.
CLI::Validator positive_finite_number(const std::string& unit = {});
/// A non-negative decimal integer ("-1", "1.5", "0x10" are refused). Add it
/// with Option::transform (check() would not let it drop leading zeros, and
/// CLI11 reads "010" as octal).
CLI::Validator non_negative_integer();
/// A list option ("a,b,c", or a repeated value) that must not be empty when given.
CLI::Option* non_empty_list(CLI::Option* option);
/// An option (e.g. a file name) whose value must not be the empty string.
CLI::Option* non_empty_value(CLI::Option* option);

/// Ends the parse with a usage error (exit 2) whose message is `message`;
/// for checks after parsing, e.g. options that make no sense together.
[[noreturn]] void throw_usage_error(const std::string& message);

/// Runs the body of subcommand `tool`: usage errors (CLI::ParseError) pass
/// through; any other exception is a data or I/O error, printed on `err` with
/// the prefix, and ends the program with ExitCode::data_error. `out` is flushed
/// first so the error follows any report already printed.
void run_reporting_errors(const std::string& tool, std::ostream& out, std::ostream& err,
                          const std::function<void()>& body);

/// Parses `args` (without the program name) with `app` and runs the selected
/// subcommand. Returns the exit status: --help and --version 0; CLI11's own
/// errors (unknown option, bad value, missing argument, excludes ...) are
/// printed on `err` with the prefix of the subcommand and return 2; errors of
/// a subcommand return the code it ended with.
int run_command_line(CLI::App& app, const std::vector<std::string>& args, std::ostream& out,
                     std::ostream& err);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_CLI_CONVENTIONS_HPP

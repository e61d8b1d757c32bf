// cli_conventions.cpp: the shared command-line convention (cli_conventions.hpp).
#include "sinkwatch/ground/cli_conventions.hpp"

#include <cmath>
#include <cstdlib>
#include <ostream>

namespace sinkwatch {
namespace ground {
namespace {

// The whole of `text` as a finite double, or false.
bool parse_finite(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(value);
}

}  // namespace

std::string error_prefix(const std::string& tool) {
  return tool.empty() ? std::string("sinkwatch: ") : "sinkwatch " + tool + ": ";
}

void add_verbosity_flags(CLI::App& sub, Verbosity& verbosity) {
  CLI::Option* quiet = sub.add_flag("-q,--quiet", verbosity.quiet, "print only errors on stderr");
  CLI::Option* verbose = sub.add_flag("-v,--verbose", verbosity.verbose, "print extra detail");
  quiet->excludes(verbose);
}

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        return parse_finite(text, value) ? std::string() : "'" + text + "' is not a finite number";
      },
      "finite", "finite");
}

CLI::Validator positive_finite_number(const std::string& unit) {
  const std::string bound = unit.empty() ? std::string("> 0") : "> 0 " + unit;
  return CLI::Validator(
      [bound](std::string& text) -> std::string {
        double value = 0.0;
        return parse_finite(text, value) && value > 0.0 ? std::string()
                                                         : "'" + text + "' is not a finite number " + bound;
      },
      bound, "positive finite");
}

CLI::Validator non_negative_integer() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) {
          return "'" + text + "' is not a non-negative integer";
        }
        // CLI11 reads integers with base 0: "010" would be octal.
        const std::size_t first = text.find_first_not_of('0');
        text = first == std::string::npos ? std::string("0") : text.substr(first);
        return {};
      },
      ">= 0", "non-negative integer");
}

CLI::Option* non_empty_list(CLI::Option* option) {
  return option->check(CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.find_first_not_of(" \t,") == std::string::npos) {
          return "the list is empty: give at least one value";
        }
        return {};
      },
      "", "non-empty list"));
}

CLI::Option* non_empty_value(CLI::Option* option) {
  return option->check(CLI::Validator(
      [](std::string& text) -> std::string {
        return text.empty() ? std::string("an empty value is not allowed") : std::string();
      },
      "", "non-empty value"));
}

void throw_usage_error(const std::string& message) { throw CLI::ValidationError(message); }

void run_reporting_errors(const std::string& tool, std::ostream& out, std::ostream& err,
                          const std::function<void()>& body) {
  try {
    body();
  } catch (const CLI::ParseError&) {
    throw;  // usage errors and codes already decided
  } catch (const std::exception& e) {
    out.flush();
    err << error_prefix(tool) << e.what() << '\n';
    throw CLI::RuntimeError(exit_status(ExitCode::data_error));
  }
}

int run_command_line(CLI::App& app, const std::vector<std::string>& args, std::ostream& out,
                     std::ostream& err) {
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
  try {
    app.parse(reversed);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // the subcommand has printed its message
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {
      return app.exit(e, out, err);  // --help, --help-all, --version
    }
    const std::vector<CLI::App*> selected = app.get_subcommands();
    const std::string tool = selected.empty() ? std::string() : selected.front()->get_name();
    out.flush();
    err << error_prefix(tool) << e.what() << '\n'
        << error_prefix(tool) << "see 'sinkwatch " << (tool.empty() ? std::string() : tool + " ")
        << "--help'\n";
    return exit_status(ExitCode::usage_error);
  }
  return exit_status(ExitCode::ok);
}

}  // namespace ground
}  // namespace sinkwatch

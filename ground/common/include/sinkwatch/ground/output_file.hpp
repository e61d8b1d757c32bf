// output_file.hpp: every file and standard-output write of the ground tools
// (`sinkwatch calibrate|diagnose|replay|simulate`) goes through here, so that
// they all follow one set of rules (docs/output-files.md):
//
//  - check_output_path() before any work starts: the parent directory exists
//    and is writable; an existing target is a regular file (a directory,
//    device, FIFO or socket is refused). A symbolic link is followed: the
//    file it points to is written in place of it and the link stays a link
//    (a dangling link is refused). "-" means standard output.
//  - OutputFile writes into a temporary file (mkstemp) in the target's
//    directory, checks every write, flush, fsync and close, and only then
//    renames it over the target. On any error the temporary is removed, the
//    target is untouched, and OutputError names the path and strerror.
//  - OutputFileSet: several outputs of one command, all checked up front,
//    all written to temporaries before the first rename.
//  - finish_standard_output(): standard output is flushed and its error state
//    checked at the end, so `sinkwatch simulate > /dev/full` fails.
//
// Host only (ground tools), POSIX.
#ifndef SINKWATCH_GROUND_OUTPUT_FILE_HPP
#define SINKWATCH_GROUND_OUTPUT_FILE_HPP

#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace sinkwatch {
namespace ground {

/// An output could not be written; the message names the path and the
/// system's reason (strerror).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// True for "-", the name of standard output.
bool is_standard_output(const std::string& path);

/// Checks that `path` can be written without replacing anything but a
/// regular file, and returns the path that will actually be replaced: `path`
/// itself, or the file a symbolic link points to (fully resolved). "-" is
/// returned unchanged. Throws OutputError naming the path when the parent
/// directory is missing or not writable, the target is a directory, device,
/// FIFO, socket or dangling link, or an existing target is not writable.
std::string check_output_path(const std::string& path);

/// Checks an output directory (diagnose --report DIR): it exists (a symbolic
/// link to a directory is fine) and is writable, or it does not exist and
/// its parent directory exists and is writable (it is then created, one
/// level only, by create_output_directory()). "-" is refused.
void check_output_directory(const std::string& dir);

/// Creates `dir` (one level) if it does not exist yet; throws OutputError.
void create_output_directory(const std::string& dir);

/// Flushes `out` and, when it is std::cout, the C stdout stream, and throws
/// OutputError("standard output: <strerror>") when any write to it failed.
void finish_standard_output(std::ostream& out);

/// One output, written through a temporary file and renamed into place.
///
///   OutputFile f(path);      // checks the path, creates the temporary
///   f.stream() << ...;       // or f.write(text)
///   f.commit();              // flush, fsync, close, rename; throws on error
///
/// If commit() is never reached (an exception), the destructor removes the
/// temporary and the target keeps its old content. For "-" the stream is the
/// given standard output and commit() is finish_standard_output().
class OutputFile {
 public:
  explicit OutputFile(const std::string& path, std::ostream* standard_output = nullptr);
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  OutputFile(OutputFile&&) noexcept;
  OutputFile& operator=(OutputFile&&) noexcept;
  ~OutputFile();

  /// The path as given by the user (for messages).
  const std::string& path() const;
  /// The file that commit() replaces (the link target for a symlink).
  const std::string& target() const;
  /// The temporary file, in the target's directory; empty for "-".
  const std::string& temporary_path() const;
  bool is_standard_output() const;

  std::ostream& stream();
  void write(const std::string& text);

  /// Flushes, fsyncs and closes the temporary (checked); commit() does it
  /// too. After close() another program may write the temporary in place of
  /// this process (gnuplot drawing a plot); commit() then fsyncs what it
  /// wrote and checks that it is not empty.
  void close();

  /// close(), and for a temporary another program wrote, checks that it is
  /// there and not empty and fsyncs it. commit() does it too; a set does it
  /// for every file before the first rename.
  void prepare();

  /// Renames the temporary over the target (after prepare()); throws
  /// OutputError and removes the temporary on any error.
  void commit();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// Several outputs of one command: add() checks each path at once (before
/// the command's work when called first), commit() writes every temporary
/// before the first rename, so a write error leaves every target untouched.
/// The same target named twice is refused.
class OutputFileSet {
 public:
  /// Checks `path` and creates its temporary; returns the file to write.
  OutputFile& add(const std::string& path, std::ostream* standard_output = nullptr);
  /// Prepares every file (all written, closed and checked), then renames
  /// each into place.
  void commit();
  std::size_t size() const { return files_.size(); }

 private:
  std::vector<std::unique_ptr<OutputFile>> files_;
};

/// Writes `contents` to `path` through OutputFile (check, temporary, rename).
void write_output_file(const std::string& path, const std::string& contents,
                       std::ostream* standard_output = nullptr);

}  // namespace ground
}  // namespace sinkwatch

#endif  // SINKWATCH_GROUND_OUTPUT_FILE_HPP

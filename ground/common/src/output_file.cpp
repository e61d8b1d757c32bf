// output_file.cpp: checked, atomic outputs of the ground tools
// (output_file.hpp, docs/output-files.md).
#include "sinkwatch/ground/output_file.hpp"

#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <set>
#include <streambuf>
#include <utility>

namespace sinkwatch {
namespace ground {

namespace {

std::string reason(int error) { return std::strerror(error); }

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw OutputError(path + ": " + what);
}

// The directory part of a path ("." when it has none), and the name.
std::string directory_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string name_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "not a regular file";
}

// The parent directory of `path` exists, is a directory and is writable.
void check_parent(const std::string& shown, const std::string& path) {
  const std::string dir = directory_of(path);
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0) {
    fail(shown, "cannot write here: directory " + dir + ": " + reason(errno));
  }
  if (!S_ISDIR(st.st_mode)) {
    fail(shown, "cannot write here: " + dir + " is not a directory");
  }
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    fail(shown, "cannot write here: directory " + dir + ": " + reason(errno));
  }
}

// The mode a new file gets (0666 less the umask), read without changing it
// for longer than the two calls.
mode_t new_file_mode() {
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return static_cast<mode_t>(0666 & ~mask);
}

// Writes everything, retrying short writes and EINTR; false with errno set.
bool write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (n == 0) {
      errno = EIO;
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

// A stream buffer over a file descriptor whose every write is checked; the
// first error is kept (errno) and every later write fails.
class FdBuf : public std::streambuf {
 public:
  explicit FdBuf(int fd) : fd_(fd) { setp(buffer_, buffer_ + sizeof buffer_); }
  int error() const { return error_; }
  void set_fd(int fd) { fd_ = fd; }
  // Bytes handed to this buffer so far (written or still buffered).
  std::size_t count() const { return total_ + static_cast<std::size_t>(pptr() - pbase()); }

 protected:
  int_type overflow(int_type ch) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  int sync() override { return drain() ? 0 : -1; }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (n >= static_cast<std::streamsize>(sizeof buffer_)) {
      if (!drain()) return 0;
      if (!write_all(fd_, s, static_cast<std::size_t>(n))) {
        error_ = errno;
        return 0;
      }
      total_ += static_cast<std::size_t>(n);
      return n;
    }
    return std::streambuf::xsputn(s, n);
  }

 private:
  bool drain() {
    if (error_ != 0) return false;
    const std::size_t size = static_cast<std::size_t>(pptr() - pbase());
    if (size > 0 && !write_all(fd_, pbase(), size)) {
      error_ = errno;
      return false;
    }
    total_ += size;
    setp(buffer_, buffer_ + sizeof buffer_);
    return true;
  }

  int fd_;
  int error_ = 0;
  std::size_t total_ = 0;
  char buffer_[65536];
};

}  // namespace

bool is_standard_output(const std::string& path) { return path == "-"; }

std::string check_output_path(const std::string& path) {
  if (path.empty()) throw OutputError("an output path is empty");
  if (is_standard_output(path)) return path;
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno != ENOENT) fail(path, "cannot write here: " + reason(errno));
    check_parent(path, path);
    return path;
  }
  std::string target = path;
  if (S_ISLNK(st.st_mode)) {
    char resolved[PATH_MAX];
    if (::realpath(path.c_str(), resolved) == nullptr) {
      fail(path, "refusing to write through a symbolic link that points nowhere (" + reason(errno) + ")");
    }
    target = resolved;
    if (::stat(target.c_str(), &st) != 0) fail(path, "cannot write here: " + reason(errno));
  }
  if (!S_ISREG(st.st_mode)) {
    fail(path, std::string("refusing to replace ") + kind_of(st.st_mode) +
                   (target != path ? " (the symbolic link points to " + target + ")" : std::string()) +
                   "; outputs replace only regular files");
  }
  if (::access(target.c_str(), W_OK) != 0) {
    fail(path, "the existing file is not writable: " + reason(errno));
  }
  check_parent(path, target);
  return target;
}

void check_output_directory(const std::string& dir) {
  if (dir.empty()) throw OutputError("an output directory path is empty");
  if (is_standard_output(dir)) throw OutputError("-: standard output cannot take a directory of files");
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0) {
    if (errno != ENOENT) fail(dir, "cannot write here: " + reason(errno));
    // Trailing slashes name the same directory.
    std::string trimmed = dir;
    while (trimmed.size() > 1 && trimmed.back() == '/') trimmed.pop_back();
    struct stat link {};
    if (::lstat(trimmed.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
      fail(dir, "refusing to write through a symbolic link that points nowhere");
    }
    check_parent(dir, trimmed);
    return;
  }
  if (!S_ISDIR(st.st_mode)) fail(dir, std::string("is ") + kind_of(st.st_mode) + ", not a directory");
  if (::access(dir.c_str(), W_OK | X_OK) != 0) fail(dir, "cannot write here: " + reason(errno));
}

void create_output_directory(const std::string& dir) {
  check_output_directory(dir);
  if (::mkdir(dir.c_str(), 0777) != 0 && errno != EEXIST) {
    fail(dir, "cannot create the directory: " + reason(errno));
  }
  check_output_directory(dir);
}

void finish_standard_output(std::ostream& out) {
  // The reason (errno) is known only when the failing write is this flush;
  // an earlier failure left just the stream's error state behind.
  errno = 0;
  out.flush();
  bool failed = !out;
  int error = failed ? errno : 0;
  if (&out == &std::cout) {
    errno = 0;
    if (std::fflush(stdout) != 0 || std::ferror(stdout) != 0) {
      failed = true;
      if (error == 0) error = errno;
    }
  }
  if (failed) {
    throw OutputError("standard output: write failed" + (error != 0 ? " (" + reason(error) + ")" : std::string()));
  }
}

struct OutputFile::State {
  std::string path;
  std::string target;
  std::string temporary;
  std::ostream* standard_output = nullptr;
  int fd = -1;
  bool closed = false;
  bool external = false;  // close() was called before anything was written
  bool prepared = false;  // closed, and an external writer's output checked
  bool committed = false;
  FdBuf buf{-1};
  std::ostream stream{&buf};

  void discard() {
    if (fd >= 0) {
      ::close(fd);
      fd = -1;
    }
    if (!temporary.empty() && !committed) ::unlink(temporary.c_str());
  }
  [[noreturn]] void fail_and_discard(const std::string& what, int error) {
    discard();
    committed = true;  // nothing left to remove
    throw OutputError(path + ": " + what + ": " + reason(error));
  }
};

OutputFile::OutputFile(const std::string& path, std::ostream* standard_output) : state_(new State) {
  State& s = *state_;
  s.path = path;
  s.target = check_output_path(path);
  if (ground::is_standard_output(path)) {
    s.standard_output = standard_output != nullptr ? standard_output : &std::cout;
    return;
  }
  // ".<name>.XXXXXX" would lose the extension that some writers (gnuplot
  // terminals) care about, so the random part goes first.
  std::string name = directory_of(s.target) + "/.XXXXXX." + name_of(s.target);
  std::vector<char> buffer(name.begin(), name.end());
  buffer.push_back('\0');
  const int suffix = static_cast<int>(name_of(s.target).size() + 1);
  const int fd = ::mkstemps(buffer.data(), suffix);
  if (fd < 0) fail(path, "cannot create a temporary file in " + directory_of(s.target) + ": " + reason(errno));
  s.fd = fd;
  s.temporary = buffer.data();
  s.buf.set_fd(fd);
  // Keep the mode of the file being replaced; a new file gets 0666 less the umask.
  struct stat st {};
  const mode_t mode = ::stat(s.target.c_str(), &st) == 0 ? static_cast<mode_t>(st.st_mode & 07777) : new_file_mode();
  if (::fchmod(fd, mode) != 0) s.fail_and_discard("cannot set the mode of the temporary file", errno);
}

OutputFile::OutputFile(OutputFile&&) noexcept = default;
OutputFile& OutputFile::operator=(OutputFile&&) noexcept = default;

OutputFile::~OutputFile() {
  if (state_) state_->discard();
}

const std::string& OutputFile::path() const { return state_->path; }
const std::string& OutputFile::target() const { return state_->target; }
const std::string& OutputFile::temporary_path() const { return state_->temporary; }
bool OutputFile::is_standard_output() const { return state_->standard_output != nullptr; }

std::ostream& OutputFile::stream() {
  return state_->standard_output != nullptr ? *state_->standard_output : state_->stream;
}

void OutputFile::write(const std::string& text) {
  stream().write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!stream()) {
    if (is_standard_output()) {
      finish_standard_output(stream());
    } else {
      state_->fail_and_discard("write failed", state_->buf.error() != 0 ? state_->buf.error() : EIO);
    }
  }
}

void OutputFile::close() {
  State& s = *state_;
  if (s.closed) return;
  if (s.standard_output != nullptr) {
    finish_standard_output(*s.standard_output);
    s.closed = true;
    return;
  }
  s.external = s.buf.count() == 0;
  s.stream.flush();
  if (!s.stream || s.buf.error() != 0) {
    s.fail_and_discard("write failed", s.buf.error() != 0 ? s.buf.error() : EIO);
  }
  if (::fsync(s.fd) != 0) s.fail_and_discard("fsync failed", errno);
  const int fd = s.fd;
  s.fd = -1;
  if (::close(fd) != 0) s.fail_and_discard("close failed", errno);
  s.closed = true;
}

void OutputFile::prepare() {
  State& s = *state_;
  if (s.prepared || s.committed) return;
  close();
  if (s.standard_output == nullptr && s.external) {
    // Another program may have written the temporary after close().
    struct stat st {};
    if (::stat(s.temporary.c_str(), &st) != 0) s.fail_and_discard("the output was not written", errno);
    if (st.st_size == 0) s.fail_and_discard("the output is empty", EIO);
    const int fd = ::open(s.temporary.c_str(), O_RDONLY);
    if (fd < 0 || ::fsync(fd) != 0) {
      const int error = errno;
      if (fd >= 0) ::close(fd);
      s.fail_and_discard("fsync failed", error);
    }
    ::close(fd);
  }
  s.prepared = true;
}

void OutputFile::commit() {
  State& s = *state_;
  if (s.committed) return;
  prepare();
  if (s.standard_output != nullptr) {
    s.committed = true;
    return;
  }
  // The target may have changed since the check (another program): check again.
  struct stat st {};
  if (::lstat(s.target.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    s.discard();
    s.committed = true;
    fail(s.path, std::string("refusing to replace ") + kind_of(st.st_mode) + " (it changed while this command ran)");
  }
  if (::rename(s.temporary.c_str(), s.target.c_str()) != 0) {
    s.fail_and_discard("cannot rename the temporary file " + s.temporary + " into place", errno);
  }
  s.committed = true;
  // Make the rename durable too; a directory that cannot be synced is no error.
  const int dir = ::open(directory_of(s.target).c_str(), O_RDONLY | O_DIRECTORY);
  if (dir >= 0) {
    (void)::fsync(dir);
    ::close(dir);
  }
}

OutputFile& OutputFileSet::add(const std::string& path, std::ostream* standard_output) {
  auto file = std::make_unique<OutputFile>(path, standard_output);
  for (const auto& other : files_) {
    if (!file->is_standard_output() && !other->is_standard_output() && other->target() == file->target()) {
      throw OutputError(path + ": the same file is named for two outputs (" + other->path() + ")");
    }
  }
  files_.push_back(std::move(file));
  return *files_.back();
}

void OutputFileSet::commit() {
  // Every temporary is complete before the first rename; standard output is
  // checked last.
  for (const auto& file : files_) {
    if (!file->is_standard_output()) file->prepare();
  }
  for (const auto& file : files_) {
    if (!file->is_standard_output()) file->commit();
  }
  for (const auto& file : files_) {
    if (file->is_standard_output()) file->commit();
  }
}

void write_output_file(const std::string& path, const std::string& contents, std::ostream* standard_output) {
  OutputFile file(path, standard_output);
  file.write(contents);
  file.commit();
}

}  // namespace ground
}  // namespace sinkwatch

// AtomicFile: write, flush, fsync, rename (see file_io.h). Plain POSIX calls, so that every
// failure has an errno to report; O_TMPFILE + linkat is Linux's way to a temporary file that
// cannot outlive its process.
#include "kernel/file_io.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "kernel/error.h"

namespace wedge {

namespace {

constexpr std::size_t kBufferSize = std::size_t(1) << 20;
constexpr const char* kTempInfix = ".wedge-";
constexpr const char* kTempSuffix = ".tmp";

std::string errno_text(int err) { return std::strerror(err); }

std::string folder_of(const std::string& path) {
  std::filesystem::path p(path);
  return p.has_parent_path() ? p.parent_path().string() : std::string(".");
}

std::string name_of(const std::string& path) { return std::filesystem::path(path).filename().string(); }

// ".<name>.wedge-" : what every temporary file of target `name` starts with.
std::string temp_prefix(const std::string& name) { return "." + name + kTempInfix; }

std::atomic<unsigned> temp_counter{0};

}  // namespace

FileHooks& file_hooks() {
  static FileHooks hooks{::write, ::fsync, ::close, true};
  return hooks;
}

std::size_t remove_stale_temporaries(const std::string& target) {
  const std::string dir = folder_of(target);
  const std::string prefix = temp_prefix(name_of(target));
  DIR* d = ::opendir(dir.c_str());
  if (!d) return 0;
  std::size_t removed = 0;
  const int dfd = ::dirfd(d);
  while (const dirent* e = ::readdir(d)) {
    std::string_view name(e->d_name);
    if (name.size() <= prefix.size() + 4 || name.substr(0, prefix.size()) != prefix ||
        name.substr(name.size() - 4) != kTempSuffix)
      continue;
    // ".<target>.wedge-<pid>-<n>.tmp": a writer that is still running keeps its file.
    std::string_view rest = name.substr(prefix.size());
    long pid = 0;
    std::size_t i = 0;
    while (i < rest.size() && rest[i] >= '0' && rest[i] <= '9' && pid < 1L << 30) pid = pid * 10 + (rest[i++] - '0');
    if (i == 0 || i >= rest.size() || rest[i] != '-') continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM) continue;
    // The process is gone; a writer in another pid namespace would still hold the lock.
    int fd = ::openat(dfd, e->d_name, O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::unlinkat(dfd, e->d_name, 0) == 0) ++removed;
    ::close(fd);
  }
  ::closedir(d);
  return removed;
}

AtomicFile::AtomicFile(const std::string& path) : path_(path), target_(path) {
  if (path.empty()) fail("cannot write a file with an empty name");
  // Writing through a symbolic link replaces the file it points to, not the link.
  struct stat st{};
  if (::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
    std::error_code ec;
    auto resolved = std::filesystem::weakly_canonical(path, ec);
    if (!ec) target_ = resolved.string();
  }
  dir_ = folder_of(target_);
  const bool exists = ::stat(target_.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) fail("cannot write '", path_, "': it is a folder");
  if (exists && !S_ISREG(st.st_mode)) fail("cannot write '", path_, "': it exists and is not a regular file");
  struct stat dst{};
  if (::stat(dir_.c_str(), &dst) != 0) {
    if (errno == ENOENT) fail("cannot write '", path_, "': folder '", dir_, "' does not exist");
    fail("cannot write '", path_, "': folder '", dir_, "': ", errno_text(errno));
  }
  if (!S_ISDIR(dst.st_mode)) fail("cannot write '", path_, "': '", dir_, "' is not a folder");

  remove_stale_temporaries(target_);

  const FileHooks& hooks = file_hooks();
  if (hooks.tmpfile) {
    fd_ = ::open(dir_.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    // Filesystems (and kernels) without O_TMPFILE say so with one of these; anything else is a
    // real reason not to write (permission, read-only, no space).
    if (fd_ < 0 && errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) fail_errno(errno);
  }
  if (fd_ < 0) {
    const std::string prefix = dir_ + "/" + temp_prefix(name_of(target_)) + std::to_string(::getpid()) + "-";
    for (int attempt = 0; fd_ < 0; ++attempt) {
      std::string name = prefix + std::to_string(temp_counter++) + kTempSuffix;
      fd_ = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd_ >= 0) tmp_name_ = name;
      else if (errno != EEXIST || attempt > 1000) fail_errno(errno);
    }
  }
  ::flock(fd_, LOCK_EX);  // marks the temporary as in use (see remove_stale_temporaries)
  if (exists) (void)::fchmod(fd_, st.st_mode & 07777);  // the replacement keeps the old file's mode
  buffer_.reserve(kBufferSize);
}

AtomicFile::~AtomicFile() {
  if (!committed_) discard();
}

void AtomicFile::discard() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!tmp_name_.empty()) ::unlink(tmp_name_.c_str());
  tmp_name_.clear();
}

void AtomicFile::fail_errno(int err) {
  discard();
  committed_ = true;  // nothing left to discard
  fail("cannot write '", path_, "': ", errno_text(err));
}

void AtomicFile::write(const void* data, std::size_t size) {
  if (fd_ < 0) fail("cannot write '", path_, "': the file is already closed");
  const char* p = static_cast<const char*>(data);
  if (buffer_.size() + size > kBufferSize) flush();
  if (size >= kBufferSize) {
    buffer_.assign(p, p + size);
    flush();
    return;
  }
  buffer_.insert(buffer_.end(), p, p + size);
}

void AtomicFile::flush() {
  const char* p = buffer_.data();
  std::size_t left = buffer_.size();
  while (left > 0) {
    ssize_t n = file_hooks().write(fd_, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail_errno(errno);
    if (n == 0) fail_errno(EIO);  // a regular file never takes nothing without an error
    p += n;
    left -= static_cast<std::size_t>(n);
    written_ += static_cast<std::size_t>(n);
  }
  buffer_.clear();
}

void AtomicFile::commit() {
  if (fd_ < 0) fail("cannot write '", path_, "': the file is already closed");
  flush();
  const FileHooks& hooks = file_hooks();
  if (hooks.fsync(fd_) != 0) fail_errno(errno);
  if (tmp_name_.empty()) {
    // Give the nameless file a name beside the target, so that rename() can replace the target
    // in one step (linkat cannot replace an existing file).
    const std::string prefix = dir_ + "/" + temp_prefix(name_of(target_)) + std::to_string(::getpid()) + "-";
    const std::string self = "/proc/self/fd/" + std::to_string(fd_);
    for (int attempt = 0; tmp_name_.empty(); ++attempt) {
      std::string name = prefix + std::to_string(temp_counter++) + kTempSuffix;
      if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0) tmp_name_ = name;
      else if (errno == ENOENT && ::linkat(fd_, "", AT_FDCWD, name.c_str(), AT_EMPTY_PATH) == 0) tmp_name_ = name;
      else if (errno != EEXIST || attempt > 1000) fail_errno(errno);
    }
  }
  int fd = fd_;
  fd_ = -1;
  if (hooks.close(fd) != 0) {
    int err = errno;
    fd_ = -1;
    fail_errno(err);
  }
  if (::rename(tmp_name_.c_str(), target_.c_str()) != 0) fail_errno(errno);
  tmp_name_.clear();
  committed_ = true;
  // The rename itself is made durable by syncing the folder; the new file is complete either way.
  int dfd = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    (void)::fsync(dfd);
    ::close(dfd);
  }
}

void write_file_atomically(const std::string& path, const void* data, std::size_t size) {
  AtomicFile file(path);
  file.write(data, size);
  file.commit();
}

std::string read_file(const std::string& path, std::size_t max_bytes) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused below.
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) fail("cannot read '", path, "': ", errno_text(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st{};
  if (::fstat(fd, &st) != 0) fail("cannot read '", path, "': ", errno_text(errno));
  if (S_ISDIR(st.st_mode)) fail("cannot read '", path, "': it is a folder");
  if (!S_ISREG(st.st_mode)) fail("cannot read '", path, "': not a regular file");
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size > max_bytes) fail("cannot read '", path, "': the file has ", size, " bytes, more than the limit of ", max_bytes);
  std::string bytes(size, '\0');
  std::size_t got = 0;
  while (got < size) {
    ssize_t n = ::read(fd, bytes.data() + got, size - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail("cannot read '", path, "': ", errno_text(errno));
    if (n == 0) break;  // the file shrank while we read it
    got += static_cast<std::size_t>(n);
  }
  bytes.resize(got);
  return bytes;
}

}  // namespace wedge

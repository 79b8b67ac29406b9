// Files written whole or not at all, and files read with their size known first.
//
// AtomicFile writes into a temporary file in the target's own folder and replaces the target only
// after every byte is written, flushed and fsync'ed: write, flush, fsync, rename. The old file stays
// intact on any error, and every write, flush, sync, close and rename error is reported with the
// system's reason ("cannot write 'part.stl': No space left on device").
//
// The temporary file is nameless where the filesystem allows it (Linux O_TMPFILE): a process killed
// while writing leaves nothing behind. It is given a name (".<target>.wedge-<pid>-<n>.tmp") only
// for the instant between linkat() and rename(), or for the whole write where O_TMPFILE is not
// supported. Such a named temporary is locked (flock) by its writer while it lives; the next
// AtomicFile for the same target removes the ones whose writer is gone (process not running and
// lock free), so a kill at any moment leaves at most a leftover that the next export cleans up.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <sys/types.h>

namespace wedge {

class AtomicFile {
 public:
  // Opens the temporary file; throws wedge::Error naming `path` and the reason (the folder does not
  // exist, the path is a folder, permission denied, ...).
  explicit AtomicFile(const std::string& path);
  // Without commit(): the temporary file is discarded and the target left as it was.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Buffered; a failed system write throws wedge::Error with the reason.
  void write(const void* data, std::size_t size);
  void write(std::string_view text) { write(text.data(), text.size()); }
  // Flushes, fsyncs and closes the temporary file, then puts it in place of the target. Throws
  // wedge::Error with the reason; the target is then unchanged and no temporary file is left.
  void commit();

  const std::string& path() const { return path_; }
  // How many bytes have been handed to write() so far.
  std::size_t size() const { return written_ + buffer_.size(); }

 private:
  [[noreturn]] void fail_errno(int err);  // discards the temporary file, throws with the reason
  void flush();
  void discard() noexcept;

  std::string path_;       // the target as given (for messages)
  std::string target_;     // the file to replace (a symbolic link's target)
  std::string dir_;        // its folder
  std::string tmp_name_;   // the named temporary file, if there is one
  int fd_ = -1;
  bool committed_ = false;
  std::size_t written_ = 0;
  std::vector<char> buffer_;
};

// The whole of `data` as the file `path`, through an AtomicFile.
void write_file_atomically(const std::string& path, const void* data, std::size_t size);

// Reads a whole regular file. Throws wedge::Error naming the path and the reason: it does not
// exist, it is a folder or not a regular file, it is larger than `max_bytes`, a read failed.
std::string read_file(const std::string& path, std::size_t max_bytes = std::size_t(1) << 32);

// Removes the leftover named temporary files of `target` whose writer is gone (see above); returns
// how many were removed. AtomicFile calls it for its own target.
std::size_t remove_stale_temporaries(const std::string& target);

// The system calls AtomicFile makes, replaceable by tests to inject failures at any byte. The
// defaults are ::write, ::fsync and ::close; `tmpfile` false forces the named-temporary path.
struct FileHooks {
  ssize_t (*write)(int fd, const void* data, std::size_t size);
  int (*fsync)(int fd);
  int (*close)(int fd);
  bool tmpfile;
};
FileHooks& file_hooks();

}  // namespace wedge

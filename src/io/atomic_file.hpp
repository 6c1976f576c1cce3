#pragma once
// Files are written to a temporary name in the same directory and renamed, so a
// reader (or a crash) never sees a half-written file.
#include <filesystem>
#include <fstream>
#include <functional>
#include <ostream>
#include <string_view>

namespace vpc {

void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// The same, with the content produced by `write` on a binary stream (no copy
/// of the whole file in memory).
void write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// A file written at a temporary name beside `path` (NAME.tmp.PID) and renamed to
/// `path` by commit(), for content produced over time (checkpoint pieces, array by
/// array). A failure to open or to write waits for commit() or throw_if_failed(), so that
/// a process goes on to its next collective step; the temporary file is removed unless
/// it was committed.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// The temporary file's stream, binary (seekable).
  std::ostream& stream() { return out_; }
  /// Throws vpc::Error if the file could not be opened or a write failed.
  void throw_if_failed() const;
  /// Flushes and closes the file and renames it to `path`; throws vpc::Error on failure.
  void commit();

 private:
  std::filesystem::path path_, tmp_;
  std::ofstream out_;
  bool opened_ = false, committed_ = false;
};

}  // namespace vpc

#include "io/atomic_file.hpp"

#include "core/error.hpp"

#include <cstdio>
#include <unistd.h>

namespace vpc {

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  write_file_atomic(path, [&](std::ostream& out) { out.write(content.data(), static_cast<std::streamsize>(content.size())); });
}

void write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  AtomicFile file(path);
  file.throw_if_failed();
  write(file.stream());
  file.commit();
}

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)) {
  tmp_ = path_;
  tmp_ += ".tmp." + std::to_string(::getpid());
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  opened_ = out_.good();
}

AtomicFile::~AtomicFile() {
  if (committed_ || !opened_) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(tmp_, ec);
}

void AtomicFile::throw_if_failed() const {
  require(opened_, "cannot open '{}' for writing", tmp_.string());
  require(out_.good(), "error while writing '{}' (disk full?)", tmp_.string());
}

void AtomicFile::commit() {
  throw_if_failed();
  out_.flush();
  throw_if_failed();
  out_.close();
  require(!out_.fail(), "error while writing '{}' (disk full?)", tmp_.string());
  std::error_code ec;
  std::filesystem::rename(tmp_, path_, ec);
  if (ec) fail("cannot rename a temporary file to '{}'", path_.string());  // the destructor removes it
  committed_ = true;
}

}  // namespace vpc

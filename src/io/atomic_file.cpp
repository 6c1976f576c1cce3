#include "io/atomic_file.hpp"

#include "core/error.hpp"

#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace vpc {

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  write_file_atomic(path, [&](std::ostream& out) { out.write(content.data(), static_cast<std::streamsize>(content.size())); });
}

void write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  std::filesystem::path tmp = path;
  tmp += ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    require(out.good(), "cannot open '{}' for writing", tmp.string());
    write(out);
    out.flush();
    require(out.good(), "error while writing '{}' (disk full?)", tmp.string());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    fail("cannot rename a temporary file to '{}'", path.string());
  }
}

}  // namespace vpc

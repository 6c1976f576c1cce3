#pragma once
// Shared by the fuzz targets: a scratch folder for the files a target writes.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <stdlib.h>  // mkdtemp

namespace vpc::fuzz {

/// A fresh folder for this process's temporary files (under $TMPDIR), removed
/// when the process exits normally.
inline const std::filesystem::path& scratch_dir() {
  struct Dir {
    std::filesystem::path path;
    Dir() {
      std::string tmpl = (std::filesystem::temp_directory_path() / "vpc_fuzz_XXXXXX").string();
      if (!mkdtemp(tmpl.data())) std::abort();
      path = tmpl;
    }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

}  // namespace vpc::fuzz

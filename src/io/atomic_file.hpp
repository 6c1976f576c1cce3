#pragma once
// Files are written to a temporary name in the same directory and renamed, so a
// reader (or a crash) never sees a half-written file.
#include <filesystem>
#include <string_view>

namespace vpc {

void write_file_atomic(const std::filesystem::path& path, std::string_view content);

}  // namespace vpc

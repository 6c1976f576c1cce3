#pragma once
// Files are written to a temporary name in the same directory and renamed, so a
// reader (or a crash) never sees a half-written file.
#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>

namespace vpc {

void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// The same, with the content produced by `write` on a binary stream (no copy
/// of the whole file in memory).
void write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

}  // namespace vpc

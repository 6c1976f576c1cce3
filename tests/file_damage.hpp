#pragma once
// Damage done to a file on purpose, for the tests of what reads it back (checkpoints).
#include <filesystem>
#include <fstream>

namespace vpc::test {

/// Flips one byte in the middle of a file.
inline void flip_a_byte(const std::filesystem::path& file) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  const auto at = static_cast<std::streamoff>(std::filesystem::file_size(file) / 2);
  char c;
  f.seekg(at);
  f.read(&c, 1);
  c = static_cast<char>(c ^ 0x5a);
  f.seekp(at);
  f.write(&c, 1);
}

}  // namespace vpc::test

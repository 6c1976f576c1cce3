#pragma once
// The case files of cases/*.toml, compiled into the program.
#include <string_view>
#include <vector>

namespace vpc {

struct ShippedCase {
  std::string_view name;  // the file's stem, e.g. "paper-2d"
  std::string_view text;  // its TOML
};

const std::vector<ShippedCase>& shipped_cases();

}  // namespace vpc

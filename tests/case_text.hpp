#pragma once
// Case-file texts in the tests: a variant of a text with one piece replaced, and the message of
// the vpc::Error that reading a text gives (the located errors of the case file).
#include "core/error.hpp"
#include "io/case_file.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace vpc::test {

/// The friction lines of the shipped shear cases (shear-2d, shear-3d), which tests replace.
inline const std::string kShippedCoulomb = "friction = \"coulomb\"\nmu = 0.3";

/// `text` with its first occurrence of `from` replaced by `to` (a test failure where it is missing).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not in the case";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// The message of the vpc::Error that parse_case gives for `text` read as `file` with `sets`;
/// "(no error)" where it reads it.
inline std::string case_error(const std::string& text, const std::string& file,
                              const std::vector<std::string>& sets = {}) {
  try {
    parse_case(text, file, ".", {.sets = sets});
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace vpc::test

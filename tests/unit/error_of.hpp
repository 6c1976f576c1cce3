#pragma once
// The message of the vpc::Error that `f` throws, and a test that it says what it should.
#include "core/error.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <string>

namespace vpc {

inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no vpc::Error thrown)";
}

/// Expects `f` to throw a vpc::Error whose message contains `part`.
inline void expect_error(const std::function<void()>& f, const std::string& part) {
  const std::string m = error_of(f);
  EXPECT_NE(m.find(part), std::string::npos) << "message: " << m << "\nexpected to contain: " << part;
}

}  // namespace vpc

#pragma once
// The message of the vpc::Error that `f` throws, for tests of error messages.
#include "core/error.hpp"

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

}  // namespace vpc

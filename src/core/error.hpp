#pragma once
// One error type for everything a user can cause (bad options, bad case data,
// a solver that cannot converge). Internal invariants use assert().
#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace vpc {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// An Error raised alike on every process of a distributed run (the same step
/// failed everywhere, or la::collective shared one rank's error): the
/// program reports it once and ends every process normally, without an abort.
class CollectiveError : public Error {
 public:
  using Error::Error;
};

/// Throws vpc::Error with a fmt-formatted message.
template <typename... Args>
[[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) {
  throw Error(fmt::format(f, std::forward<Args>(args)...));
}

/// Throws vpc::Error unless `ok`; for user-caused conditions (always checked).
template <typename... Args>
void require(bool ok, fmt::format_string<Args...> f, Args&&... args) {
  if (!ok) throw Error(fmt::format(f, std::forward<Args>(args)...));
}

/// Runs `check` and puts `where` (a file:line:column, an option, a case name) before
/// the message of a vpc::Error it throws: a check written once, located by its caller.
template <typename Check>
auto located(const std::string& where, Check&& check) {
  try {
    return check();
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
}

}  // namespace vpc

#pragma once
// Child processes without a shell: the program and its arguments are passed as
// an argument vector (posix_spawn), so no character of a path (', ", ;, $(…),
// backticks, spaces) is ever interpreted (issue 11, item 1).
#include <string>
#include <vector>

namespace vpc {

struct ChildResult {
  bool started = false;  // false: the program could not be started (`error` says why)
  int exit_code = -1;    // the child's exit status; -1 if it died by a signal
  int signal = 0;        // the signal that ended it, 0 if none
  std::string error;     // why it could not be started (strerror)
  bool ok() const { return started && exit_code == 0; }
};

/// Runs argv[0] (an absolute path; no PATH search) with the arguments argv[1..],
/// inheriting stdin/stdout/stderr (silenced with `quiet`: both go to /dev/null),
/// and waits for it.
ChildResult run_child(const std::vector<std::string>& argv, bool quiet = false);

}  // namespace vpc

#pragma once
// Files of the io tests: a fresh directory per test and process, a file's bytes, and a
// stepper's checkpoint as a run writes it.
#include "io/checkpoint.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace vpc::test {

/// An empty directory <tmp>/<prefix><name>_<pid>.
inline std::filesystem::path fresh_dir(const std::string& prefix, const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / (prefix + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The stepper's state now as a checkpoint (no PVD entries, zero totals).
inline Checkpoint checkpoint_of(const TimeStepper& s) {
  Checkpoint c;
  c.case_name = s.problem().name;
  c.fingerprint = problem_fingerprint(s);
  c.problem_key = problem_key(s);
  c.snapshot = s.snapshot();
  c.times = s.times();
  c.grid = UniformGrid::of(s.problem(), s.times());  // as the stepper's writer stores them
  c.step_control = s.step_control_state().values();
  return c;
}

}  // namespace vpc::test

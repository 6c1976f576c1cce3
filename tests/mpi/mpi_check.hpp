#pragma once
// A check of an MPI test program: failed when it fails on any rank, counted once and printed by
// rank 0 (the programs end by printing PASSED or FAILED from the count).
#include "la/comm.hpp"

#include <fmt/format.h>

#include <string>

namespace vpc::test {

inline int failures = 0;

inline void check(bool ok, const std::string& what, const la::Comm& comm) {
  if (!comm.all(ok)) {
    ++failures;
    if (comm.rank() == 0) fmt::print("FAILED: {}\n", what);
  }
}

}  // namespace vpc::test

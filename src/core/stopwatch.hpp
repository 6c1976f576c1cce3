#pragma once
// Wall time of a phase, for the set-up stages, the step phases and the adaptations' reports.
#include <chrono>

namespace vpc {

/// Seconds of the steady clock since t0.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace vpc

#pragma once
// Progress of a run: a one-line bar with step, time, ETA, active contact nodes
// and min β on a terminal; plain log lines (about every 5 %) otherwise.
#include "scheme/time_stepper.hpp"

#include <chrono>
#include <cstdio>

namespace vpc {

class Progress {
 public:
  Progress(int n_steps, bool quiet);
  void update(const StepReport& r);
  void finish();

 private:
  int n_steps_;
  bool quiet_, tty_;
  std::chrono::steady_clock::time_point t0_;
  bool line_open_ = false;
};

}  // namespace vpc

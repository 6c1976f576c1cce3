#pragma once
// Progress of a run: a one-line bar with step, time, ETA, active contact nodes
// and min β on a terminal; plain log lines (about every 5 %) otherwise.
#include "scheme/time_stepper.hpp"

#include <chrono>
#include <cstdio>
#include <string>

namespace vpc {

/// The set-up stages as they start and end ("  assembly ... 0.012 s"), so a long
/// set-up is never a blank screen (SolverChoice::on_setup_stage).
class StageLog {
 public:
  explicit StageLog(bool quiet) : quiet_(quiet) {}
  /// `seconds` < 0: the stage starts; else it ended after that long.
  void operator()(const std::string& stage, double seconds) const;

 private:
  bool quiet_;
};

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

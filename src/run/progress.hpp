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
  /// `n_steps` 0: error-controlled steps, whose progress is t / T.
  Progress(int n_steps, double final_time, bool quiet);
  void update(const StepReport& r);
  void finish();

 private:
  int n_steps_;
  double final_time_;
  double next_line_t_ = 0;  // error-controlled steps: a line each T / 20
  bool quiet_, tty_;
  std::chrono::steady_clock::time_point t0_;
  bool line_open_ = false;
};

}  // namespace vpc

#include "run/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace vpc {

Progress::Progress(int n_steps, double final_time, bool quiet)
    : n_steps_(n_steps), final_time_(final_time), quiet_(quiet), tty_(::isatty(STDOUT_FILENO) != 0), t0_(std::chrono::steady_clock::now()) {
  if (!quiet_ && !tty_)
    fmt::print("  {:>6} {:>9} {:>6} {:>13} {:>5} {:>9} {:>5} {:>9} {:>10} {:>10}\n", "step", "t", "active",
               "contact force", "it_c", "res_c", "it_d", "res_d", "beta_min", "beta_max");
}

void Progress::update(const StepReport& r) {
  if (quiet_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  if (tty_) {
    const double frac = n_steps_ > 0 ? static_cast<double>(r.n) / n_steps_ : r.t / final_time_;
    const double eta = frac > 0 ? elapsed * (1 - frac) / frac : 0.0;
    const int width = 28, filled = std::clamp(static_cast<int>(frac * width), 0, width);
    const std::string of = n_steps_ > 0 ? fmt::format("/{}", n_steps_) : fmt::format(" (k = {:.3g})", r.k);
    // ESC[K clears the rest of the line: a shorter line leaves no characters of the last one.
    fmt::print("\r  [{}{}] step {}{}  t = {:.4g}  ETA {:.1f} s  active {}  min beta {:.6f}\x1b[K",
               std::string(filled, '#'), std::string(width - filled, '.'), r.n, of, r.t, eta, r.contact.n_active,
               r.beta_min);
    std::fflush(stdout);
    line_open_ = true;
    if (!r.ok) finish();
    return;
  }
  const int every = std::max(1, n_steps_ / 20);
  const bool due = n_steps_ > 0 ? r.n % every == 0 || r.n == n_steps_ : r.t >= next_line_t_ || r.t >= final_time_;
  if (due && n_steps_ == 0) next_line_t_ = (std::floor(r.t / final_time_ * 20) + 1) * final_time_ / 20;
  if (due || !r.ok) {
    fmt::print("  {:6d} {:9.4g} {:6d} {:13.6e} {:5d} {:9.2e} {:5d} {:9.2e} {:10.6f} {:10.6f}\n", r.n, r.t,
               r.contact.n_active, r.contact.total_force, r.contact.iterations, r.contact.residuals.max(),
               r.damage.iterations, r.damage.kkt_residual, r.beta_min, r.beta_max);
    std::fflush(stdout);
  }
}

void StageLog::operator()(const std::string& stage, double seconds) const {
  if (quiet_) return;
  if (seconds < 0)
    fmt::print("  {} ...", stage);
  else
    fmt::print(" {:.3f} s\n", seconds);
  std::fflush(stdout);
}

void Progress::finish() {
  if (line_open_) fmt::print("\n");
  line_open_ = false;
}

}  // namespace vpc

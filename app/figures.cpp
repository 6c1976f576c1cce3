#include "figures.hpp"

#include "child_process.hpp"
#include "run/interrupt.hpp"
#include "core/error.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>

namespace vpc {

namespace fs = std::filesystem;

std::string python_interpreter() {
  const char* env = std::getenv("VPCONTACT_PYTHON");
  return env && *env ? env : "/usr/bin/python3";
}

fs::path script_path(const char* variable, const char* name) {
  if (const char* env = std::getenv(variable)) return env;
  return fs::path(VPC_SOURCE_DIR) / "scripts" / name;
}

namespace {

/// Why figures cannot be drawn on this machine, empty if they can.
std::string missing_plot_tools(const std::string& python) {
  const ChildResult probe = run_child({python, "-c", "import numpy, matplotlib"}, true);
  if (!probe.started) return fmt::format("python3 ('{}') cannot be started: {}", python, probe.error);
  if (!probe.ok()) return fmt::format("'{}' has no numpy or matplotlib", python);
  return "";
}

}  // namespace

void draw_figures(const fs::path& outdir, const PlotOptions& options, bool after_run) {
  const fs::path script = script_path("VPCONTACT_PLOT_SCRIPT", "vpcontact_plot.py");
  require(fs::is_regular_file(script), "plot: the figure script '{}' is missing", script.string());
  std::error_code ec;
  require(fs::is_directory(outdir, ec), "plot: '{}' is not a directory{}", outdir.string(),
          ec ? ": " + ec.message() : "");
  const std::string python = python_interpreter();
  if (const std::string missing = missing_plot_tools(python); !missing.empty()) {
    const std::string how = fmt::format(
        "install Debian's python3-numpy and python3-matplotlib (bash scripts/install-deps.sh does), then run "
        "`vpcontact plot {}`", shell_quote(outdir.string()));
    require(after_run, "plot: {}; {}", missing, how);
    std::fflush(stdout);
    fmt::print(stderr, "vpcontact: warning: figures not drawn: {}; the run's results are complete. To draw them, {}\n",
               missing, how);
    return;
  }
  std::fflush(stdout);
  const ChildResult r =
      run_child({python, script.string(), outdir.string(), "--format", options.format, "--dpi", fmt::format("{}", options.dpi)});
  const std::string how_it_ended = !r.started ? fmt::format("could not be started: {}", r.error)
                                   : r.signal ? fmt::format("was killed by signal {}", r.signal)
                                              : fmt::format("exited with code {}; its message is above", r.exit_code);
  require(r.ok(), "plot: drawing the figures of '{}' failed: {} {}{}", outdir.string(), script.string(), how_it_ended,
          after_run ? " (the run itself finished; its results are complete)" : "");
  fmt::print("  figures ({}) in {}/\n", options.format, (outdir / "figures").string());
}

}  // namespace vpc

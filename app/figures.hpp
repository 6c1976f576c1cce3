#pragma once
// The paper's figures of a run's output directory, drawn by
// scripts/vpcontact_plot.py (python3 with numpy and matplotlib), started
// without a shell (child_process.hpp). Used by `vpcontact plot` and `run --plot`
// on both engines.
#include <filesystem>
#include <string>

namespace vpc {

/// Checked where they are read (the command line: add_plot_options).
struct PlotOptions {
  std::string format = "png";  // png, pdf or svg
  double dpi = 150;
};

/// The interpreter: $VPCONTACT_PYTHON, else /usr/bin/python3 (Debian's, which finds python3-matplotlib).
std::string python_interpreter();

/// The script `name` of the source tree's scripts/, or the file the environment variable `variable` names.
std::filesystem::path script_path(const char* variable, const char* name);

/// Draws the figures into outdir/figures/. Throws vpc::Error when they cannot be
/// drawn, except that after a run (`after_run`) a missing python3, numpy or
/// matplotlib is only a warning on stderr (the run's results are complete
/// without the figures); a failure of the script itself is an error either way.
void draw_figures(const std::filesystem::path& outdir, const PlotOptions& options, bool after_run);

}  // namespace vpc

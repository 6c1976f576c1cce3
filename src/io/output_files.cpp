#include "io/output_files.hpp"

#include "core/error.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <unistd.h>

namespace vpc {

namespace fs = std::filesystem;

namespace {

bool all_digits(std::string_view s) {
  return !s.empty() && s.find_first_not_of("0123456789") == std::string_view::npos;
}

/// NAME.tmp.PID, as write_file_atomic names its temporary files.
bool is_temporary(const std::string& name) {
  const auto at = name.rfind(".tmp.");
  return at != std::string::npos && at > 0 && all_digits(std::string_view(name).substr(at + 5));
}

bool is_figure(const fs::path& p) {
  const auto ext = p.extension();
  return ext == ".png" || ext == ".pdf" || ext == ".svg";
}

void remove_file(const fs::path& p, std::vector<fs::path>& removed) {
  std::error_code ec;
  fs::remove(p, ec);
  require(!ec, "cannot remove '{}' of an earlier run: {}", p.string(), ec.message());
  removed.push_back(p);
}

}  // namespace

void prepare_output_directory(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  require(!ec, "cannot create the output directory '{}': {}", dir.string(), ec.message());
  require(fs::is_directory(dir, ec), "the output directory '{}' exists and is not a directory", dir.string());
  // Permissions alone do not tell (read-only mounts, root): try to create a file.
  const fs::path probe = dir / (".vpcontact-write-test." + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  require(fd >= 0, "cannot write in the output directory '{}': {}", dir.string(), std::strerror(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

bool is_run_output(const std::string& name) {
  if (name == "solution.pvd" || name == "history.csv" || name == "probes.csv" || name == "summary.json") return true;
  if (name.starts_with("solution_") && (name.ends_with(".vtu") || name.ends_with(".pvtu"))) return true;
  return name.starts_with("checkpoint_") && name.ends_with(".bin");
}

std::vector<fs::path> remove_run_outputs(const fs::path& dir) {
  std::vector<fs::path> removed;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return removed;
  std::vector<fs::path> doomed;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file(ec) && (is_run_output(name) || is_temporary(name))) doomed.push_back(e.path());
  }
  require(!ec, "cannot list the output directory '{}': {}", dir.string(), ec.message());
  for (const auto& p : doomed) remove_file(p, removed);
  const fs::path figures = dir / "figures";
  if (fs::is_directory(figures, ec)) {
    doomed.clear();
    for (const auto& e : fs::directory_iterator(figures, ec))
      if (e.is_regular_file(ec) && is_figure(e.path())) doomed.push_back(e.path());
    for (const auto& p : doomed) remove_file(p, removed);
    if (fs::is_empty(figures, ec)) fs::remove(figures, ec);
  }
  return removed;
}

int remove_temporary_files(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> doomed;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (is_temporary(e.path().filename().string())) doomed.push_back(e.path());
  int n = 0;
  for (const auto& p : doomed) n += fs::remove(p, ec) ? 1 : 0;
  return n;
}

}  // namespace vpc

#include "la/memory_estimate.hpp"

#include "core/error.hpp"
#include "core/quote.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

namespace vpc {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A cgroup limit of 2⁶⁰ bytes or more means "no limit" (v1 writes 2⁶³ − 4096).
constexpr double kNoCgroupLimit = 1152921504606846976.0;

/// MemAvailable of /proc/meminfo in bytes, or +inf if unknown.
double mem_available() {
  std::ifstream in("/proc/meminfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("MemAvailable:", 0) == 0) return 1024.0 * std::strtod(line.c_str() + 13, nullptr);
  return kInf;
}

/// The first number in `file`, or +inf if absent, "max" or no limit.
double read_limit(const std::string& file) {
  std::ifstream in(file);
  std::string s;
  if (!(in >> s) || s == "max") return kInf;
  const double v = std::strtod(s.c_str(), nullptr);
  return v > 0 && v < kNoCgroupLimit ? v : kInf;
}

/// This process's cgroup memory limit (v2 or v1), or +inf.
double cgroup_limit() {
  std::ifstream in("/proc/self/cgroup");
  double limit = kInf;
  for (std::string line; std::getline(in, line);) {
    // "0::/path" (v2) or "N:memory:/path" (v1); the mount may show the path or be its root.
    const auto a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const std::string controllers = line.substr(a + 1, b - a - 1), path = line.substr(b + 1);
    if (controllers.empty()) {
      limit = std::min({limit, read_limit("/sys/fs/cgroup" + path + "/memory.max"),
                        read_limit("/sys/fs/cgroup/memory.max")});
    } else if (controllers.find("memory") != std::string::npos) {
      limit = std::min({limit, read_limit("/sys/fs/cgroup/memory" + path + "/memory.limit_in_bytes"),
                        read_limit("/sys/fs/cgroup/memory/memory.limit_in_bytes")});
    }
  }
  return limit;
}

}  // namespace

std::string format_bytes(double bytes) {
  static const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  if (!std::isfinite(bytes)) return "unlimited";
  int u = 0;
  while (bytes >= 1000 && u < 6) {  // "0.98 GiB", not "1e+03 MiB"
    bytes /= 1024;
    ++u;
  }
  return u == 0 ? fmt::format("{:.0f} B", bytes) : fmt::format("{:.3g} {}", bytes, units[u]);
}

double parse_memory_size(const std::string& text, const std::string& where) {
  std::string t;
  for (char ch : text)
    if (!std::isspace(static_cast<unsigned char>(ch))) t += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (t == "unlimited" || t == "none") return kInf;
  const char* begin = t.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  std::string unit(end);
  if (unit.size() > 1 && unit.back() == 'b') unit.pop_back();            // "GB", "GiB"
  if (unit.size() > 1 && unit.back() == 'i') unit.pop_back();            // "Gi"
  const std::string units = "kmgt";
  double scale = 1;
  if (unit.size() == 1 && units.find(unit[0]) != std::string::npos)
    scale = std::pow(1024.0, static_cast<double>(units.find(unit[0]) + 1));
  else if (!unit.empty() && unit != "b")
    end = const_cast<char*>(begin);  // an unknown unit: not a size
  require(end != begin && std::isfinite(v) && v > 0,
          "{}: expected a memory size > 0 such as 512M, 8G or 2000000000 (bytes), or \"unlimited\"; got {}", where,
          quote(text));
  return v * scale;
}

MemoryLimit memory_limit(const std::string& requested) {
  if (!requested.empty()) return {parse_memory_size(requested, "--memory-limit"), "--memory-limit"};
  if (const char* env = std::getenv(kMemoryLimitVariable); env && *env)
    return {parse_memory_size(env, kMemoryLimitVariable), kMemoryLimitVariable};
  const double available = mem_available(), cgroup = cgroup_limit();
  if (cgroup < available) return {cgroup, "the memory limit of this process's cgroup"};
  return {available, "the memory available (MemAvailable in /proc/meminfo)"};
}

double MemoryEstimate::total() const {
  double s = 0;
  for (const auto& [what, bytes] : parts) s += bytes;
  return s;
}

std::string MemoryEstimate::describe() const {
  std::string s;
  for (const auto& [what, bytes] : parts) {
    if (bytes <= 0) continue;
    s += fmt::format("{}{} {}", s.empty() ? "" : " + ", what, format_bytes(bytes));
  }
  return s;
}

MemoryEstimate estimate_run_memory(double mesh_bytes, double matrix_bytes, const FactorEstimate& K,
                                   const FactorEstimate& H, bool damage_active_set, double contact_nodes) {
  MemoryEstimate e;
  e.add("mesh and state", mesh_bytes);
  e.add("matrices", matrix_bytes);
  e.add("factor of K", K.factor_bytes);
  e.add("factor of H", H.factor_bytes);
  e.add("factorization workspace", std::max(K.workspace_bytes, H.workspace_bytes));
  if (damage_active_set) e.add("damage solver's stored columns", 0.5 * H.factor_bytes);
  // The Delassus matrix S = N K⁻¹Nᵀ and its reduced copy (dense), and the sparse
  // Y = L⁻¹PNᵀ (solvers/dual_active_set.cpp), made up to min(256 MiB, K's factor) to form S,
  // twice while S is formed (la/gram.hpp reads it by rows), then kept up to half the factor. A
  // column of Y is nonzero on the elimination-tree path of its dof: taken as 4√(entries of L), the
  // order of the top separators (n^{2/3} in 3D), at most n.
  const double y_column = std::min(K.rows, 4 * std::sqrt(K.entries));
  const double y_bytes = std::min({12 * contact_nodes * y_column, 256.0 * 1024 * 1024, K.factor_bytes});
  e.add("contact solver", 2 * 8 * contact_nodes * contact_nodes + 2 * y_bytes);
  return e;
}

void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit, const std::string& what,
                  const std::string& path, const std::string& instead) {
  if (estimate.total() <= limit.bytes) return;
  throw MemoryLimitError(fmt::format(
      "{}: {} would need about {} of memory ({}), more than the limit of {} set by {}; {}use a coarser mesh, or set "
      "the limit with --memory-limit SIZE or {}=SIZE (e.g. 16G, or unlimited)",
      what, path, format_bytes(estimate.total()), estimate.describe(), format_bytes(limit.bytes), limit.source,
      instead.empty() ? "" : instead + ", ", kMemoryLimitVariable));
}

}  // namespace vpc

#pragma once
// Whether a run fits in memory (issue 11): what it will hold, by part, against
// the memory it may use, checked before the costly factorizations. The factors'
// sizes come from CHOLMOD's symbolic analysis (la::LinearSolver::analyze).
#include "la/linear_solver.hpp"

#include "core/error.hpp"

#include <string>
#include <utility>
#include <vector>

namespace vpc {

/// "1.50 GiB", "320 MiB", "12.0 KiB", "100 B".
std::string format_bytes(double bytes);

/// A memory size: bytes with an optional unit K, M, G or T (powers of 1024; "KB",
/// "KiB", "k" also accepted), e.g. "512M", "1.5G", "2000000000"; "unlimited" (or
/// "none") for no limit (+inf). Throws vpc::Error naming `where`.
double parse_memory_size(const std::string& text, const std::string& where);

struct MemoryLimit {
  double bytes = 0;    // +inf: no limit
  std::string source;  // where it comes from, for the message
};

/// The environment variable that sets the limit (as --memory-limit does).
inline constexpr const char* kMemoryLimitVariable = "VPCONTACT_MEMORY_LIMIT";

/// The memory a run may use: `requested` (--memory-limit) if not empty, else
/// $VPCONTACT_MEMORY_LIMIT if set, else the machine's: MemAvailable of
/// /proc/meminfo, or the cgroup's limit (v2 memory.max, v1 memory.limit_in_bytes)
/// when lower.
MemoryLimit memory_limit(const std::string& requested = "");

/// An estimate by part (what, bytes).
struct MemoryEstimate {
  std::vector<std::pair<std::string, double>> parts;
  void add(std::string what, double bytes) { parts.emplace_back(std::move(what), bytes); }
  double total() const;
  /// "mesh and state 1.2 MiB + matrices 3.4 MiB + ..."
  std::string describe() const;
};

/// The memory of a run of the scheme: the mesh and per-cell state, the sparse
/// matrices, the factors of K and H (from their symbolic analyses) and the larger
/// of their factorization workspaces, the active-set damage solver's stored columns
/// (at most half H's factor, box_qp.cpp), and the contact solver's dense m × m
/// matrices and stored columns (at most min(256 MiB, half K's factor)).
MemoryEstimate estimate_run_memory(double mesh_bytes, double matrix_bytes, const FactorEstimate& K,
                                   const FactorEstimate& H, bool damage_active_set, double contact_nodes);

/// A run that does not fit (check_memory, run/solver_plan.hpp's refusals).
class MemoryLimitError : public Error {
 public:
  using Error::Error;
};

/// Throws MemoryLimitError naming the estimate by part and the limit when the estimate
/// exceeds it; `what` names the run, `path` what would need the memory ("the run", "MUMPS")
/// and `instead` (if not empty) the option that would fit.
void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit, const std::string& what,
                  const std::string& path = "the run", const std::string& instead = "");

}  // namespace vpc

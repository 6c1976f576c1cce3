#include "process_policy.hpp"

#include <malloc.h>
#include <unistd.h>

#include <cstdlib>

namespace vpc {

void ensure_passive_omp_wait(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  ::setenv("OMP_WAIT_POLICY", "passive", 1);
  ::execv("/proc/self/exe", argv);  // returns only on failure: then run as we are
}

void keep_freed_memory() {
  // Blocks up to 32 MiB (glibc's largest mmap threshold) come from the heap,
  // and the heap's top is returned to the kernel only beyond 1 GiB of free space.
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024 * 1024);
  // Larger blocks (K, its copies, the multigrid's products) are mapped, so that freeing one gives
  // it back at once. SuperLU_DIST, which Debian's PETSc loads with this program (and which it does
  // not use), turns mapping off as it loads (M_MMAP_MAX = 0): every block then came from the heap,
  // where freed ones left holes; foundation-3d n = 70 on 2 ranks held 0.51 GB a rank more than it
  // used at its end (docs/parallel.md, "Where the memory goes"). 65,536 is glibc's default.
  mallopt(M_MMAP_MAX, 65536);
}

}  // namespace vpc

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
}

}  // namespace vpc

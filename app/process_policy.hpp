#pragma once
// Process-wide settings of the programs (vpcontact, vpcontact-bench), not of the
// library: a program calls both first thing in main().
namespace vpc {

/// OpenMP workers that spin after a parallel loop steal the core the next solve
/// needs whenever the machine is shared (measured here: a 2-core run 2-3x slower
/// under load; docs/performance.md). libgomp reads OMP_WAIT_POLICY once, when it
/// is loaded: without a value in the environment this sets "passive" and
/// re-executes the program (once; a value given by the user is kept).
void ensure_passive_omp_wait(char** argv);

/// Large vectors (solves with a block of right-hand sides, per-step loads) are
/// allocated and freed every step. glibc gives blocks above its mmap threshold
/// back to the kernel at once, so each new one costs a page fault per 4 KiB; on
/// virtual machines that fault is slow (measured here: the 16-column partial
/// solves of the contact set-up took 2-3x longer, 20 ms of 30 in page faults).
/// Freed memory then stays with the process and is reused; the peak resident
/// memory is unchanged (it is a maximum). Blocks beyond 32 MiB are mapped, and
/// given back when freed.
void keep_freed_memory();

}  // namespace vpc

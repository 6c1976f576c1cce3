#pragma once
// OpenMP workers that spin after a parallel loop steal the core the next solve
// needs whenever the machine is shared (measured here: a 2-core run 2-3x slower
// under load; docs/performance.md). libgomp reads OMP_WAIT_POLICY once, when it
// is loaded, so a program calls this first thing in main(): without a value in
// the environment it sets "passive" and re-executes itself (once; a value given
// by the user is kept).
namespace vpc {

void ensure_passive_omp_wait(char** argv);

}  // namespace vpc

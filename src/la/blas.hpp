#pragma once
// The BLAS at run time (OpenBLAS when present, found with dlsym; other BLAS
// libraries are left alone).
//
// Threads: measured here (docs/performance.md), the supernodal factorization
// gains from all cores, but the forward/back solves of every time step are
// 1.5–2.5x slower with two BLAS threads than with one.
//
// One-column products: this library defines dgemm_ and dtrsm_, which hand a
// product or triangular solve with ONE right-hand column to dgemv_ / dtrsv_ and
// everything else to the BLAS's own routine. MUMPS's solve phase calls GEMM and
// TRSM with one column for a single right-hand side, and OpenBLAS 0.3.21 (Debian
// 12) packs whole panels of the factor for them (profile of a MUMPS solve:
// dgemm_itcopy/incopy 18 % of the run); as GEMV the same solve is 25 % faster
// (docs/performance.md). Same operation, same BLAS, a different summation order:
// results change at round-off only.
namespace vpc {

/// Sets the number of BLAS threads; returns false when the BLAS has no such control.
bool set_blas_threads(int n);
/// The number of BLAS threads, or 0 when unknown.
int blas_threads();
/// C += AᵀA on C's lower triangle (BLAS dsyrk): A is rows × n (column-major, leading dimension
/// lda ≥ rows), C is n × n (column-major, leading dimension n); the upper triangle is left alone.
void syrk_lower_add(const double* A, int rows, int lda, int n, double* C);
/// Calls of dgemm_/dtrsm_ handed to dgemv_/dtrsv_ so far (for tests and reports).
long long blas_one_column_calls();

}  // namespace vpc

#pragma once
// OpenBLAS threading, set at run time when the BLAS is OpenBLAS (found with
// dlsym; a no-op with another BLAS). Measured here (docs/performance.md): the
// supernodal factorization gains from all cores, but the forward/back solves of
// every time step are 1.5–2.5x slower with two BLAS threads than with one.
namespace vpc {

/// Sets the number of BLAS threads; returns false when the BLAS has no such control.
bool set_blas_threads(int n);
/// The number of BLAS threads, or 0 when unknown.
int blas_threads();

}  // namespace vpc

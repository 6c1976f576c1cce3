#include "la/blas.hpp"

#include <dlfcn.h>

#include <atomic>

namespace vpc {

bool set_blas_threads(int n) {
  using Set = void (*)(int);
  static const auto set = reinterpret_cast<Set>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!set) return false;
  set(n);
  return true;
}

int blas_threads() {
  using Get = int (*)();
  static const auto get = reinterpret_cast<Get>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  return get ? get() : 0;
}

namespace {
std::atomic<long long> one_column_calls{0};
}  // namespace

long long blas_one_column_calls() { return one_column_calls.load(std::memory_order_relaxed); }

}  // namespace vpc

// The Fortran BLAS interface (every argument by address; callers from Fortran add
// hidden string lengths at the end, which the C routines below ignore as the
// BLAS's own do).
extern "C" {
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a, const int* lda,
            const double* x, const int* incx, const double* beta, double* y, const int* incy);
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a, const int* lda,
            double* x, const int* incx);
void dscal_(const int* n, const double* alpha, double* x, const int* incx);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* beta, double* c, const int* ldc);

void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb);
}

namespace {

bool is(const char* flag, char upper) { return *flag == upper || *flag == upper - 'A' + 'a'; }

template <typename F>
F next_definition(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

}  // namespace

void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc) {
  // C (m × 1) = α op(A) op(B) + β C, op(B) a column of k entries.
  if (*n == 1 && *m > 0 && *k > 0) {
    const int one = 1, incb = is(transb, 'N') ? 1 : *ldb;
    if (is(transa, 'N'))
      dgemv_("N", m, k, alpha, a, lda, b, &incb, beta, c, &one);
    else
      dgemv_("T", k, m, alpha, a, lda, b, &incb, beta, c, &one);
    vpc::one_column_calls.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  using Gemm = decltype(&dgemm_);
  static const auto gemm = next_definition<Gemm>("dgemm_");
  gemm(transa, transb, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc);
}

void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb) {
  // op(A) x = α b for one column b of m entries (α = 0 is left to the BLAS: it
  // sets B to zero without reading it).
  if (is(side, 'L') && *n == 1 && *m > 0 && *alpha != 0) {
    const int one = 1;
    if (*alpha != 1) dscal_(m, alpha, b, &one);
    dtrsv_(uplo, transa, diag, m, a, lda, b, &one);
    vpc::one_column_calls.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  using Trsm = decltype(&dtrsm_);
  static const auto trsm = next_definition<Trsm>("dtrsm_");
  trsm(side, uplo, transa, diag, m, n, alpha, a, lda, b, ldb);
}

void vpc::syrk_lower_add(const double* A, int rows, int lda, int n, double* C) {
  if (rows <= 0 || n <= 0) return;
  const double one = 1;
  dsyrk_("L", "T", &n, &rows, &one, A, &lda, &one, C, &n);
}

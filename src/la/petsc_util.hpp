#pragma once
// Small helpers around PETSc and MPI: errors become vpc::Error (the caller's
// top level aborts the communicator, so no rank waits forever for one that
// failed), owning handles for PETSc objects, and a few collectives.
#include "core/error.hpp"

#include <mpi.h>
#include <petscksp.h>

#include <utility>
#include <vector>

namespace vpc {

/// Throws vpc::Error with PETSc's message for a nonzero error code.
[[noreturn]] void petsc_fail(PetscErrorCode code, const char* expr, const char* file, int line);

}  // namespace vpc

/// Calls a PETSc function; a nonzero error code becomes a vpc::Error.
#define VPC_PETSC(...)                                                         \
  do {                                                                         \
    const PetscErrorCode vpc_ierr_ = (__VA_ARGS__);                            \
    if (vpc_ierr_) ::vpc::petsc_fail(vpc_ierr_, #__VA_ARGS__, __FILE__, __LINE__); \
  } while (0)

namespace vpc {

/// An owning handle for a PETSc object (Mat, Vec, KSP, IS, ...): destroyed with
/// the matching XxxDestroy when it goes out of scope.
template <typename T, PetscErrorCode (*Destroy)(T*)>
class PetscHandle {
 public:
  PetscHandle() = default;
  explicit PetscHandle(T h) : h_(h) {}
  PetscHandle(const PetscHandle&) = delete;
  PetscHandle& operator=(const PetscHandle&) = delete;
  PetscHandle(PetscHandle&& o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
  PetscHandle& operator=(PetscHandle&& o) noexcept {
    if (this != &o) {
      reset();
      h_ = std::exchange(o.h_, nullptr);
    }
    return *this;
  }
  ~PetscHandle() { reset(); }
  void reset() {
    if (h_) Destroy(&h_);
    h_ = nullptr;
  }
  T get() const { return h_; }
  T* out() {
    reset();
    return &h_;
  }
  operator T() const { return h_; }
  explicit operator bool() const { return h_ != nullptr; }

 private:
  T h_ = nullptr;
};

using PMat = PetscHandle<Mat, MatDestroy>;
using PVec = PetscHandle<Vec, VecDestroy>;
using PKsp = PetscHandle<KSP, KSPDestroy>;
using PIs = PetscHandle<IS, ISDestroy>;

inline int comm_rank(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}
inline int comm_size(MPI_Comm comm) {
  int s = 1;
  MPI_Comm_size(comm, &s);
  return s;
}

double allreduce_max(MPI_Comm comm, double v);
double allreduce_min(MPI_Comm comm, double v);
double allreduce_sum(MPI_Comm comm, double v);
long long allreduce_sum(MPI_Comm comm, long long v);
bool allreduce_and(MPI_Comm comm, bool v);
bool allreduce_or(MPI_Comm comm, bool v);
/// Element-wise sum over the ranks, in place (every rank gets the same values).
void allreduce_sum(MPI_Comm comm, double* v, int n);

}  // namespace vpc

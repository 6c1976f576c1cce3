#include "la/petsc_util.hpp"

#include <fmt/format.h>

namespace vpc {

void petsc_fail(PetscErrorCode code, const char* expr, const char* file, int line) {
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  fail("PETSc error {} ({}) in {} at {}:{}", code, text ? text : "unknown", expr, file, line);
}

double allreduce_max(MPI_Comm comm, double v) {
  double r = v;
  MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_MAX, comm);
  return r;
}
double allreduce_min(MPI_Comm comm, double v) {
  double r = v;
  MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_MIN, comm);
  return r;
}
double allreduce_sum(MPI_Comm comm, double v) {
  double r = v;
  MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_SUM, comm);
  return r;
}
long long allreduce_sum(MPI_Comm comm, long long v) {
  long long r = v;
  MPI_Allreduce(&v, &r, 1, MPI_LONG_LONG, MPI_SUM, comm);
  return r;
}
bool allreduce_and(MPI_Comm comm, bool v) {
  int a = v ? 1 : 0, r = a;
  MPI_Allreduce(&a, &r, 1, MPI_INT, MPI_LAND, comm);
  return r != 0;
}
bool allreduce_or(MPI_Comm comm, bool v) {
  int a = v ? 1 : 0, r = a;
  MPI_Allreduce(&a, &r, 1, MPI_INT, MPI_LOR, comm);
  return r != 0;
}
void allreduce_sum(MPI_Comm comm, double* v, int n) {
  if (n > 0) MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, MPI_SUM, comm);
}

}  // namespace vpc

#include "la/mumps_schur.hpp"

#include <dmumps_c.h>
#include <petscmat.h>

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace vpc::la {

namespace {

constexpr int kBroadcastColumns = 1024;

// The MUMPS manual's 1-based names for its control and information arrays.
int& icntl(DMUMPS_STRUC_C& id, int i) { return id.icntl[i - 1]; }
int infog(const DMUMPS_STRUC_C& id, int i) { return id.infog[i - 1]; }

/// One MUMPS instance on `comm`, ended (job −2) however the scope is left.
class MumpsInstance {
 public:
  explicit MumpsInstance(MPI_Comm comm) {
    id_.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(comm));
    id_.par = 1;  // the host works too
    id_.sym = 2;  // symmetric, not definite: LDLᵀ (the augmented matrix is indefinite)
    run(-1);
    for (int i = 1; i <= 3; ++i) icntl(id_, i) = -1;  // no output: failures become vpc::Error
    icntl(id_, 4) = 0;
  }
  MumpsInstance(const MumpsInstance&) = delete;
  MumpsInstance& operator=(const MumpsInstance&) = delete;
  ~MumpsInstance() { run(-2); }
  DMUMPS_STRUC_C& id() { return id_; }
  void run(int job) {
    id_.job = job;
    dmumps_c(&id_);
  }

 private:
  DMUMPS_STRUC_C id_{};
};

}  // namespace

Eigen::MatrixXd mumps_schur_complement(MPI_Comm comm, Mat A, const Eigen::SparseMatrix<double>& B_local,
                                       const std::vector<int>& rows, int m, const char* what) {
  PetscInt begin = 0, end = 0, n = 0;
  VPC_PETSC(MatGetOwnershipRange(A, &begin, &end));
  VPC_PETSC(MatGetSize(A, &n, nullptr));
  require(n + m < INT32_MAX, "the {}: the augmented matrix has {} rows, more than MUMPS' 32-bit indices", what, n + m);
  // This rank's entries of the lower triangle of [A Bᵀ; B 0], 1-based: A's owned rows, B's rows
  // (numbered after A's), and the Schur block's diagonal (zeros, on rank 0) so that every Schur
  // unknown is in the pattern.
  std::vector<MUMPS_INT> irn, jcn;
  std::vector<double> val;
  auto add = [&](PetscInt i, PetscInt j, double v) {
    irn.push_back(static_cast<MUMPS_INT>(i + 1));
    jcn.push_back(static_cast<MUMPS_INT>(j + 1));
    val.push_back(v);
  };
  for (PetscInt i = begin; i < end; ++i) {
    PetscInt nc = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    VPC_PETSC(MatGetRow(A, i, &nc, &cols, &vals));
    for (PetscInt k = 0; k < nc; ++k)
      if (cols[k] <= i) add(i, cols[k], vals[k]);
    VPC_PETSC(MatRestoreRow(A, i, &nc, &cols, &vals));
  }
  for (int k = 0; k < B_local.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(B_local, k); it; ++it)
      add(n + rows[static_cast<std::size_t>(it.row())], begin + it.col(), it.value());
  const bool host = comm_rank(comm) == 0;
  std::vector<MUMPS_INT> schur_vars;
  if (host)
    for (int j = 0; j < m; ++j) {
      add(n + j, n + j, 0.0);
      schur_vars.push_back(static_cast<MUMPS_INT>(n + j + 1));
    }
  std::vector<double> schur(host ? static_cast<std::size_t>(m) * m : 0);

  MumpsInstance mumps(comm);
  DMUMPS_STRUC_C& id = mumps.id();
  icntl(id, 5) = 0;   // assembled
  icntl(id, 18) = 3;  // distributed entries: each rank gives its own
  icntl(id, 19) = 1;  // the Schur complement centralized on the host
  id.n = static_cast<MUMPS_INT>(n + m);
  id.nnz_loc = static_cast<MUMPS_INT8>(val.size());
  id.irn_loc = irn.data();
  id.jcn_loc = jcn.data();
  id.a_loc = val.data();
  id.size_schur = m;
  if (host) {
    id.listvar_schur = schur_vars.data();
    id.schur = schur.data();
  }
  // MUMPS sizes its workspace from the analysis plus ICNTL(14) percent; dynamic scheduling on
  // several ranks can need more (INFOG(1) = −9 or −8): the factorization is redone with twice the
  // margin, up to 800 %, as PetscFactor does for K.
  icntl(id, 14) = 50;
  mumps.run(1);
  require(infog(id, 1) >= 0, "the {}: MUMPS' analysis of [K Bᵀ; B 0] failed (INFOG(1) = {}, INFOG(2) = {})", what,
          infog(id, 1), infog(id, 2));
  for (;;) {
    mumps.run(2);
    const int err = infog(id, 1);
    if ((err == -8 || err == -9) && icntl(id, 14) < 800) {
      icntl(id, 14) *= 2;
      continue;
    }
    require(err >= 0, "the {}: MUMPS' factorization of [K Bᵀ; B 0] failed (INFOG(1) = {}, INFOG(2) = {})", what, err,
            infog(id, 2));
    break;
  }

  // The Schur block of the factorization is 0 − B A⁻¹ Bᵀ. For a symmetric matrix MUMPS returns its
  // lower triangle by rows (ICNTL(19) = 1), the upper one of this column-major view; the rest of the
  // array is its workspace, not zeros (dome-3d: entries 200x S's own).
  Eigen::MatrixXd S(m, m);
  if (host) S = -Eigen::MatrixXd(Eigen::Map<const Eigen::MatrixXd>(schur.data(), m, m).selfadjointView<Eigen::Upper>());
  for (int j0 = 0; j0 < m; j0 += kBroadcastColumns)  // counts within MPI's int
    MPI_Bcast(S.col(j0).data(), static_cast<int>(m) * std::min(kBroadcastColumns, m - j0), MPI_DOUBLE, 0, comm);
  return S;
}

MumpsFactorSize mumps_factor_size(Mat F) {
  PetscInt entries = 0;
  PetscReal flops = 0;
  VPC_PETSC(MatMumpsGetInfog(F, 29, &entries));  // negative: millions of entries
  VPC_PETSC(MatMumpsGetRinfog(F, 3, &flops));
  return {entries < 0 ? -1e6 * static_cast<double>(entries) : static_cast<double>(entries), flops};
}

}  // namespace vpc::la

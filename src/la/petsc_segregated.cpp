#include "la/petsc_segregated.hpp"

#include <algorithm>
#include <climits>

namespace vpc::la {

bool several_fields(MPI_Comm comm, const std::vector<int>& field) {
  int lo = INT_MAX, hi = INT_MIN;  // over no rows: neither bound moves
  for (const int f : field) {
    lo = std::min(lo, f);
    hi = std::max(hi, f);
  }
  MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_INT, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_INT, MPI_MAX, comm);
  return lo < hi;
}

namespace {

/// The field of every column this rank's rows of A reach: its own rows' from `field`, the
/// others' gathered from their owners.
class ColumnFields {
 public:
  ColumnFields(Mat A, const std::vector<int>& field) : field_(field) {
    VPC_PETSC(MatGetOwnershipRange(A, &begin_, &end_));
    require(static_cast<PetscInt>(field.size()) == end_ - begin_,
            "internal: {} fields for {} owned rows", field.size(), end_ - begin_);
    for (PetscInt row = begin_; row < end_; ++row) {
      PetscInt nc = 0;
      const PetscInt* cols = nullptr;
      VPC_PETSC(MatGetRow(A, row, &nc, &cols, nullptr));
      for (PetscInt k = 0; k < nc; ++k)
        if (cols[k] < begin_ || cols[k] >= end_) ghosts_.push_back(cols[k]);
      VPC_PETSC(MatRestoreRow(A, row, &nc, &cols, nullptr));
    }
    std::sort(ghosts_.begin(), ghosts_.end());
    ghosts_.erase(std::unique(ghosts_.begin(), ghosts_.end()), ghosts_.end());
    PVec owned, gathered;
    VPC_PETSC(MatCreateVecs(A, owned.out(), nullptr));
    double* a = nullptr;
    VPC_PETSC(VecGetArray(owned, &a));
    for (std::size_t i = 0; i < field.size(); ++i) a[i] = field[i];
    VPC_PETSC(VecRestoreArray(owned, &a));
    const auto n_ghosts = static_cast<PetscInt>(ghosts_.size());
    VPC_PETSC(VecCreateSeq(PETSC_COMM_SELF, n_ghosts, gathered.out()));
    PIs is;
    VPC_PETSC(ISCreateGeneral(PETSC_COMM_SELF, n_ghosts, ghosts_.data(), PETSC_USE_POINTER, is.out()));
    VecScatter scatter = nullptr;
    VPC_PETSC(VecScatterCreate(owned, is, gathered, nullptr, &scatter));
    VPC_PETSC(VecScatterBegin(scatter, owned, gathered, INSERT_VALUES, SCATTER_FORWARD));
    VPC_PETSC(VecScatterEnd(scatter, owned, gathered, INSERT_VALUES, SCATTER_FORWARD));
    VPC_PETSC(VecScatterDestroy(&scatter));
    const double* g = nullptr;
    VPC_PETSC(VecGetArrayRead(gathered, &g));
    ghost_field_.assign(g, g + n_ghosts);
    VPC_PETSC(VecRestoreArrayRead(gathered, &g));
  }
  int operator()(PetscInt col) const {
    if (col >= begin_ && col < end_) return field_[static_cast<std::size_t>(col - begin_)];
    const auto at = std::lower_bound(ghosts_.begin(), ghosts_.end(), col) - ghosts_.begin();
    return static_cast<int>(ghost_field_[static_cast<std::size_t>(at)]);
  }
  PetscInt begin() const { return begin_; }
  PetscInt end() const { return end_; }

 private:
  const std::vector<int>& field_;
  PetscInt begin_ = 0, end_ = 0;
  std::vector<PetscInt> ghosts_;
  std::vector<double> ghost_field_;
};

}  // namespace

PMat within_fields(Mat A, const std::vector<int>& field) {
  const ColumnFields field_of(A, field);
  const PetscInt begin = field_of.begin(), end = field_of.end(), n = end - begin;
  std::vector<PetscInt> d_nnz(static_cast<std::size_t>(n)), o_nnz(static_cast<std::size_t>(n));
  for (PetscInt row = begin; row < end; ++row) {
    PetscInt nc = 0;
    const PetscInt* cols = nullptr;
    VPC_PETSC(MatGetRow(A, row, &nc, &cols, nullptr));
    const int f = field[static_cast<std::size_t>(row - begin)];
    for (PetscInt k = 0; k < nc; ++k)
      if (field_of(cols[k]) == f) ++(cols[k] >= begin && cols[k] < end ? d_nnz : o_nnz)[row - begin];
    VPC_PETSC(MatRestoreRow(A, row, &nc, &cols, nullptr));
  }
  PetscInt N = 0, bs = 1;
  VPC_PETSC(MatGetSize(A, &N, nullptr));
  VPC_PETSC(MatGetBlockSize(A, &bs));
  PMat B;
  VPC_PETSC(MatCreate(PetscObjectComm(reinterpret_cast<PetscObject>(A)), B.out()));
  VPC_PETSC(MatSetType(B, MATAIJ));
  VPC_PETSC(MatSetSizes(B, n, n, N, N));
  VPC_PETSC(MatSetBlockSize(B, bs));
  VPC_PETSC(MatSeqAIJSetPreallocation(B, 0, d_nnz.data()));
  VPC_PETSC(MatMPIAIJSetPreallocation(B, 0, d_nnz.data(), 0, o_nnz.data()));
  std::vector<PetscInt> keep_cols;
  std::vector<PetscScalar> keep_vals;
  for (PetscInt row = begin; row < end; ++row) {
    PetscInt nc = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    VPC_PETSC(MatGetRow(A, row, &nc, &cols, &vals));
    const int f = field[static_cast<std::size_t>(row - begin)];
    keep_cols.clear();
    keep_vals.clear();
    for (PetscInt k = 0; k < nc; ++k)
      if (field_of(cols[k]) == f) {
        keep_cols.push_back(cols[k]);
        keep_vals.push_back(vals[k]);
      }
    VPC_PETSC(MatSetValues(B, 1, &row, static_cast<PetscInt>(keep_cols.size()), keep_cols.data(), keep_vals.data(),
                           INSERT_VALUES));
    VPC_PETSC(MatRestoreRow(A, row, &nc, &cols, &vals));
  }
  VPC_PETSC(MatAssemblyBegin(B, MAT_FINAL_ASSEMBLY));
  VPC_PETSC(MatAssemblyEnd(B, MAT_FINAL_ASSEMBLY));
  VPC_PETSC(MatSetOption(B, MAT_SYMMETRIC, PETSC_TRUE));
  VPC_PETSC(MatSetOption(B, MAT_SPD, PETSC_TRUE));
  return B;
}

void galerkin_levels(PC pc, Mat A) {
  PetscInt levels = 0;
  VPC_PETSC(PCMGGetLevels(pc, &levels));
  PMat product;  // the last coarse operator formed (the smoothers hold their own references)
  Mat fine = A;
  for (PetscInt l = levels - 1; l >= 0; --l) {
    KSP smoother = nullptr;
    VPC_PETSC(PCMGGetSmoother(pc, l, &smoother));
    VPC_PETSC(KSPSetOperators(smoother, fine, fine));
    if (l == 0) break;
    VPC_PETSC(PCMGSetResidual(pc, l, PCMGResidualDefault, fine));
    Mat P = nullptr;
    VPC_PETSC(PCMGGetInterpolation(pc, l, &P));
    PMat coarse;
    VPC_PETSC(MatPtAP(fine, P, MAT_INITIAL_MATRIX, 2.0, coarse.out()));
    product = std::move(coarse);
    fine = product;
  }
}

}  // namespace vpc::la

#include "solvers/dual_active_set.hpp"

#include "core/error.hpp"
#include "la/gram.hpp"
#include "solvers/bond_dual.hpp"
#include "solvers/box_qp.hpp"
#include "solvers/compliance_dual.hpp"
#include "solvers/friction_dual.hpp"

#include <algorithm>
#include <limits>
#include <optional>

namespace vpc {

namespace {

/// The same block size on every rank (block solves are collective).
int common_block_columns(const la::Comm& comm, Eigen::Index n_owned, int most) {
  return static_cast<int>(comm.min(rhs_block_columns(n_owned, most)));
}

/// Every row's bond a_i of the step (ContactConstraints::bond; 0 where a set made by hand has none yet),
/// the same on every rank.
Vector replicated_bonds(const la::Comm& comm, const ContactConstraints& c) {
  return replicate(comm, c, c.bond.size() ? c.bond : Vector(Vector::Zero(c.bond_length.size())));
}

/// The dual problem of a step for b = B K⁻¹F − [g; h] (replicated), chosen once where the solver is
/// built (ActiveSetContactSolver::dual_problem): the box QP, the nonlinear compliance law's Newton,
/// or friction's dual over each node's block.
class DualProblem {
 public:
  virtual ~DualProblem() = default;
  /// Solves it for λ (warm-started from it); `c`: the constraints with the step's data.
  virtual BoxQpResult solve(const la::Comm& comm, const ContactConstraints& c, const Vector& b, Vector& lambda) = 0;
  /// The report of its λ (contact_report or friction_report).
  virtual ContactReport report(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F, const Vector& u,
                               const Vector& lambda, const BoxQpResult& qp) const {
    return contact_report(K, c, F, u, lambda, qp.converged, qp.iterations);
  }
  /// How it is solved, for describe() ("" for the box QP).
  virtual std::string describe() const = 0;
};

/// The box QP with S + diag(1/k) over each row's dual set: λ ≥ lower (0 but for a law that carries
/// a tension), λ ≤ the law's dual_upper.
class BoxDual final : public DualProblem {
 public:
  BoxDual(Eigen::MatrixXd S, Vector lo, Vector hi) : S_(std::move(S)), lo_(std::move(lo)), hi_(std::move(hi)) {}
  BoxQpResult solve(const la::Comm&, const ContactConstraints&, const Vector& b, Vector& lambda) override {
    return solve_box_qp(S_, b, lo_, hi_, lambda);
  }
  std::string describe() const override { return ""; }

 private:
  DenseBoxQpOperator S_;
  Vector lo_, hi_;
};

/// A normal law that is not linear on some row: solve_compliance_dual on S itself.
/// With bonds (adhesion) its rows' tension branches too, the step's bonds a_i read from the constraints:
/// λ_i ≥ lower_i − a_i L_i.
class ComplianceDual final : public DualProblem {
 public:
  ComplianceDual(Eigen::MatrixXd S, std::vector<const ContactLaw*> laws, Vector compliance, Vector lower,
                 Vector bond_length)
      : S_(std::move(S)), laws_(std::move(laws)), compliance_(std::move(compliance)), lower_(std::move(lower)),
        bond_length_(std::move(bond_length)) {}
  BoxQpResult solve(const la::Comm& comm, const ContactConstraints& c, const Vector& b, Vector& lambda) override {
    if (bond_length_.size() == 0)
      return solve_compliance_dual(S_, b, laws_, compliance_, lambda, kComplianceDualIterations, lower_);
    const Vector bond = replicated_bonds(comm, c);
    const Vector lower = lower_ - bond.cwiseProduct(bond_length_);
    return solve_compliance_dual(S_, b, laws_, compliance_, lambda, kComplianceDualIterations, lower, bond,
                                 bond_length_);
  }
  std::string describe() const override {
    return bond_length_.size() ? "; semismooth Newton for the bonds' tension branches (adhesion)"
                               : "; semismooth Newton for the nonlinear compliance law";
  }

 private:
  Eigen::MatrixXd S_;
  std::vector<const ContactLaw*> laws_;
  Vector compliance_, lower_, bond_length_;  // bond_length_: every row's L_i (replicated), empty without adhesion
};

/// Adhesion's bonds (SPEC §9) on Signorini and linear compliance rows (bond_dual.hpp): the three-state
/// active set, or the split box QP where its sets come back or a law bounds λ above.
class BondDual final : public DualProblem {
 public:
  BondDual(Eigen::MatrixXd S, Vector spring, Vector lower, Vector upper, Vector bond_length)
      : S_(std::move(S)), spring_(std::move(spring)), lower_(std::move(lower)), upper_(std::move(upper)),
        bond_length_(std::move(bond_length)),
        unbounded_((upper_.array() == std::numeric_limits<double>::infinity()).all()) {}
  BoxQpResult solve(const la::Comm& comm, const ContactConstraints& c, const Vector& b, Vector& lambda) override {
    const Vector bond = replicated_bonds(comm, c);
    if (lambda.size() != S_.rows()) lambda = Vector::Zero(S_.rows());
    if (unbounded_) {
      Vector x = lambda;
      if (const std::optional<BoxQpResult> r = solve_bond_states(S_, spring_, lower_, bond, bond_length_, b, x)) {
        lambda = x;
        return *r;
      }
    }
    BoxQpResult r = solve_bond_split(S_, spring_, lower_, upper_, bond, bond_length_, b, lambda);
    ++r.cycles;  // (the three states' sets came back: counted as the box QP counts its own)
    return r;
  }
  std::string describe() const override { return "; the bonds' tension branches (adhesion) by a three-state active set"; }

 private:
  Eigen::MatrixXd S_;  // S + diag(1/k) on the linear compliance rows
  Vector spring_;      // 1/k_j on those rows, 0 on rigid ones (every row's, replicated)
  Vector lower_, upper_, bond_length_;
  bool unbounded_;  // no law here bounds λ above (the three states' premise)
};

/// Friction (friction_dual.hpp): each node's block λ_ν, λ_τ over its sets, with the step's bounds.
class FrictionDual final : public DualProblem {
 public:
  FrictionDual(Eigen::MatrixXd S, FrictionDualSets sets) : S_(std::move(S)), sets_(std::move(sets)), lo_(sets_.lo) {}
  BoxQpResult solve(const la::Comm& comm, const ContactConstraints& c, const Vector& b, Vector& lambda) override {
    sets_.tresca = replicate(comm, c, c.tresca);
    if (sets_.bond_length.size()) {  // adhesion: the step's bonds, each bonded node's λ_ν ≥ lo − a L
      sets_.bond = replicated_bonds(comm, c);
      sets_.lo = lo_ - sets_.bond.cwiseProduct(sets_.bond_length);
    }
    if (!c.shear_bonded) return solve_friction_dual(S_, b, sets_, lambda);
    return solve_with_shear_bonds(comm, c, b, lambda);
  }
  ContactReport report(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F, const Vector& u,
                       const Vector& lambda, const BoxQpResult& qp) const override {
    return friction_report(K, c, F, u, lambda, qp.converged, qp.iterations);
  }
  std::string describe() const override {
    if (!sets_.force_law.empty())
      return "; friction and the nonlinear compliance law by semismooth Newton (Alart-Curnier) on the dual";
    if (!shear_compliance_.empty()) return "; the tangential bonds as Tresca discs with their compliance on the dual";
    if (sets_.coulomb()) return "; Coulomb friction by semismooth Newton (Alart-Curnier) on the dual";
    if (sets_.block == 2) return "; Tresca friction as a box QP";
    return "; Tresca friction by semismooth Newton (Alart-Curnier) on the dual";
  }

 private:
  /// A tangential bond (SPEC §9's γ_τ, ContactConstraints::shear_bond) on frictionless rows: λ_τ = a_τ P_L(Δ + v)
  /// with Δ = b_τ − (Sλ)_τ is the optimality condition of the Tresca problem of the disc of radius a_τ L
  /// (bound_of) for S + diag(1/a_τ) and b_τ + v: S's tangential diagonal takes the step's 1/a_τ (changed
  /// in place from the last step's), b the stretch v_{n−1}.
  BoxQpResult solve_with_shear_bonds(const la::Comm& comm, const ContactConstraints& c, const Vector& b, Vector& lambda) {
    const int d = c.block, t = d - 1;
    const Vector zero = Vector::Zero(static_cast<Eigen::Index>(c.rows.size()));
    const Vector shear = replicate(comm, c, c.shear_bond.size() ? c.shear_bond : zero);
    sets_.tresca += shear.cwiseProduct(sets_.bond_length);  // (every row's L, replicated at set-up)
    if (shear_compliance_.empty()) shear_compliance_.assign(static_cast<std::size_t>(c.m), 0.0);
    const Vector stretch = c.bond_stretch.size() ? c.bond_stretch : Vector(Vector::Zero(c.T.rows()));
    const Vector offsets = replicate_blocks(comm, c, zero, stretch);
    Vector b_bonded = b;
    for (int i = 0; i < c.m; ++i) {
      const double compliance = shear[i] > 0 ? 1 / shear[i] : 0.0;
      for (int j = 0; j < t; ++j) {
        const int k = i * d + 1 + j;
        if (!sets_.tangent[static_cast<std::size_t>(i * t + j)]) continue;  // held at 0 (a symmetry plane)
        S_.add_to_diagonal(k, compliance - shear_compliance_[static_cast<std::size_t>(i)]);
        if (shear[i] > 0) b_bonded[k] += offsets[k];
      }
      shear_compliance_[static_cast<std::size_t>(i)] = compliance;
    }
    return solve_friction_dual(S_, b_bonded, sets_, lambda);
  }

  DenseBoxQpOperator S_;
  FrictionDualSets sets_;
  Vector lo_;  // the normal forces' own lower bounds (the laws'), without the bonds
  std::vector<double> shear_compliance_;  // per node, the 1/a_τ S's tangential diagonal holds now
};

class ActiveSetContactSolver final : public ContactSolver {
 public:
  ActiveSetContactSolver(std::shared_ptr<const la::SpdOperator> K, std::shared_ptr<const la::LinearSolver> factor,
                         ContactConstraints c, double max_cached_share)
      : K_(std::move(K)), c_(std::move(c)), factor_(std::move(factor)) {
    // Where some rank holds pieces, every rank must sum the products with them (RemoteRows::spread,
    // set where the constraints are made): one rank alone would wait in its sum for the others.
    require(comm().all(c_.remote.spread) == comm().any(c_.remote.spread || !c_.remote.rows.empty()),
            "internal: remote pieces of contact rows on some rank, not marked spread on every rank");
    B_ = block_rows(c_, B_rows_);
    Eigen::MatrixXd S = factor_->has_halves() ? dual_matrix_from_halves(max_cached_share)
                                              : dual_matrix_from_schur_or_solves(max_cached_share);
    S = 0.5 * (S + S.transpose()).eval();
    if (!c_.laws.empty()) {  // every row's law, compliance and lower bound, the same on every rank
      const auto n = static_cast<Eigen::Index>(c_.law.size());
      const Vector all = replicate(comm(), c_, Eigen::Map<const Eigen::VectorXi>(c_.law.data(), n).cast<double>());
      const Vector datum = replicate(comm(), c_, c_.datum);
      compliance_.resize(all.size());
      lower_.resize(all.size());
      for (Eigen::Index j = 0; j < all.size(); ++j) {
        const auto law = static_cast<std::size_t>(all[j]);
        row_laws_.push_back(c_.laws[law].get());
        row_frictions_.push_back(ContactConstraints::entry(c_.frictions, law));
        compliance_[j] = row_laws_.back()->compliance(datum[j]);
        lower_[j] = row_laws_.back()->dual_lower(datum[j]);
      }
      nonlinear_ = std::ranges::any_of(row_laws_, [](const ContactLaw* l) { return !l->linear(); });
      if (comm().any(c_.adhesive())) bond_length_ = replicate(comm(), c_, c_.bond_length);
    }
    problem_ = dual_problem(std::move(S));
  }

  // N below is B (N, or [N; T] with friction) and g is g (or [g; h]: block_rows), m is m × block.
  ContactReport solve(const Vector& F, Vector& u, Vector& lambda) override {
    const int m = unknowns();
    if (lambda.size() != m) lambda = Vector::Zero(m);
    BoxQpResult r;
    if (Y_.cols() == m) {
      // One solve in two halves: y = L⁻¹PF; the dual QP min ½λᵀSλ − (N K⁻¹F − g)ᵀλ,
      // λ ≥ 0, with N K⁻¹F = Yᵀy; then u = PᵀL⁻ᵀ(y − Yλ) = K⁻¹(F − Nᵀλ).
      const Vector y = factor_->forward(F);
      r = problem_->solve(comm(), c_, Vector(Y_.transpose() * y - replicated(offsets())), lambda);
      u = factor_->backward(Vector(y - Y_ * lambda));
    } else {
      Vector u_free = u;  // the solution without contact (u: an iterative solver's initial guess)
      factor_->solve(F, u_free);
      r = problem_->solve(comm(), c_, replicated(Vector(B() * u_free - offsets())), lambda);
      if (W_.cols() == m) {
        // u = u_free − Wλ over the active rows only (λ_j = 0 elsewhere): the
        // active set is usually a part of Γ3, and each column is n_owned long.
        u = u_free;
        for (int j = 0; j < m; ++j)
          if (lambda[j] != 0) u.noalias() -= lambda[j] * W_.col(j);
      } else {
        u = u_free;
        factor_->solve(Vector(F - B().transpose() * local_of(lambda)), u);
      }
    }
    ContactReport rep = problem_->report(*K_, c_, F, u, lambda, r);
    rep.cycles = r.cycles;
    return rep;
  }
  void set_gap(const Vector& gap) override { c_.gap = checked_gap(c_, gap); }
  void set_friction(const Vector& tresca, const Vector& shift) override { set_friction_data(c_, tresca, shift); }
  void set_bond(const StepBonds& bonds) override { set_bond_data(c_, bonds); }
  const ContactConstraints& constraints() const override { return c_; }
  std::string name() const override { return "active-set"; }
  std::string describe() const override { return describe_solves() + problem_->describe(); }

 private:
  /// The step's dual problem, chosen here once: with friction its blocks' (friction_sets), else the box
  /// QP, or solve_compliance_dual where some row's law is not linear. A linear law's λ_i = k_i d₊ adds
  /// its spring's compliance 1/k_i to S_ii (the box QP of S + diag(1/k)) on the normal rows (j × block);
  /// a law that is not linear has λ_i = λ(d) on S itself.
  std::unique_ptr<DualProblem> dual_problem(Eigen::MatrixXd S) const {
    auto with_springs = [&] {
      const Eigen::Index b = c_.block;
      for (Eigen::Index j = 0; j < compliance_.size(); ++j)
        if (const ContactLaw* law = row_laws_[static_cast<std::size_t>(j)]; !law->rigid() && law->linear())
          S(j * b, j * b) += law->spring_compliance(compliance_[j]);
    };
    if (c_.frictional()) {
      with_springs();
      FrictionDualSets sets = friction_sets(comm(), c_, row_laws_, lower_, row_frictions_, S);
      sets.bond_length = bond_length_;
      if (nonlinear_) {  // friction_dual.hpp: those rows' λ_ν = λ(d) in the semismooth Newton
        for (const ContactLaw* law : row_laws_) sets.force_law.push_back(law->linear() ? nullptr : law);
        sets.compliance = compliance_;
      }
      return std::make_unique<FrictionDual>(std::move(S), std::move(sets));
    }
    if (nonlinear_) return std::make_unique<ComplianceDual>(std::move(S), row_laws_, compliance_, lower_, bond_length_);
    with_springs();
    Vector lo = Vector::Zero(c_.m), hi = Vector::Constant(c_.m, std::numeric_limits<double>::infinity());
    for (std::size_t j = 0; j < row_laws_.size(); ++j) {
      lo[static_cast<Eigen::Index>(j)] = lower_[static_cast<Eigen::Index>(j)];
      hi[static_cast<Eigen::Index>(j)] = row_laws_[j]->dual_upper();
    }
    if (bond_length_.size()) {
      Vector spring = Vector::Zero(c_.m);  // 1/k of the linear compliance rows, the springs added to S
      for (std::size_t j = 0; j < row_laws_.size(); ++j)
        if (const ContactLaw* law = row_laws_[j]; !law->rigid())
          spring[static_cast<Eigen::Index>(j)] = law->spring_compliance(compliance_[static_cast<Eigen::Index>(j)]);
      return std::make_unique<BondDual>(std::move(S), std::move(spring), std::move(lo), std::move(hi), bond_length_);
    }
    return std::make_unique<BoxDual>(std::move(S), std::move(lo), std::move(hi));
  }
  std::string describe_solves() const {
    if (Y_.cols() > 0) return "one solve per step (K's halves)";
    if (W_.cols() > 0) return "one solve per step (K⁻¹Nᵀ kept)";
    return schur_ ? "two solves per step (S by MUMPS' Schur complement)" : "two solves per step";
  }

  const la::Comm& comm() const { return K_->comm(); }

  // The constraint rows: N, or B = [N; T] with friction, node by node in λ's order (λ_ν, λ_τ), then this
  // rank's pieces of other ranks' rows (ContactConstraints::remote) alike: S, the solves and Nᵀλ see
  // whole rows as the sums of their parts over the ranks.
  int unknowns() const { return c_.m * c_.block; }
  const SparseMatrix& B() const { return B_; }
  const std::vector<int>& rows() const { return B_rows_; }
  /// g (or [g; h]) of this rank's rows of B (0 on its pieces: the owner gives a row's offset).
  Vector offsets() const { return block_offsets(c_); }
  /// The unknowns of λ (all of them, the same on every rank) from this rank's rows' values, and back.
  /// A place is once on a rank (a piece is never of its own rank's row): a row's value is its owner's
  /// plus its pieces' (exact without pieces: one value a row).
  Vector replicated(const Vector& local) const {
    Vector all = Vector::Zero(unknowns());
    for (std::size_t k = 0; k < B_rows_.size(); ++k) all[B_rows_[k]] = local[static_cast<Eigen::Index>(k)];
    comm().sum(all.data(), all.size());
    return all;
  }
  Vector local_of(const Vector& lambda) const {
    Vector l(static_cast<Eigen::Index>(B_rows_.size()));
    for (std::size_t k = 0; k < B_rows_.size(); ++k) l[static_cast<Eigen::Index>(k)] = lambda[B_rows_[k]];
    return l;
  }

  /// With K = PᵀLLᵀP: Y = L⁻¹PNᵀ (the forward half of K⁻¹Nᵀ) and S = N K⁻¹Nᵀ = YᵀY,
  /// formed once (K and N never change). A column of Y is nonzero only on the
  /// elimination-tree path of its contact dof, so Y is small and kept sparse (S from it: la/gram.hpp): kept for the
  /// steps while within min(256 MiB, `max_cached_share` of the factor), else S is formed from it
  /// and it is dropped (a step then costs two solves). Only a Y larger than the factor itself
  /// (la/memory_estimate.cpp counts that much) is abandoned for m solves: the forward halves
  /// alone cost a third of them.
  /// A factor with halves is one process's (CHOLMOD): N is whole here (no pieces).
  Eigen::MatrixXd dual_matrix_from_halves(double max_cached_share) {
    const int m = unknowns();
    const double kept_bytes = std::min(kMaxCachedBytes, max_cached_share * factor_->factor_bytes());
    const double setup_bytes = std::min(kMaxCachedBytes, factor_->factor_bytes());
    const auto n = c_.N.cols();
    // Y's compressed columns, filled block by block (value + row index: 12 bytes an entry).
    std::vector<int> outer{0}, inner;
    std::vector<double> values;
    // Dense blocks of right-hand sides: 32 columns where the factor is large beside such a block (3D: the
    // forward solves run at BLAS-3 speed, ironing-3d 40 x 20 x 12's S in 2.6 s against 4.4 s with 8), fewer
    // where a block would be more than an eighth of the factor (2D, a small factor: hertz-2d at 36,046
    // unknowns held 37 MB more in blocks of 32 than in blocks of 8, twice its factor, and took longer).
    const int most = static_cast<int>(std::clamp(factor_->factor_bytes() / (64.0 * static_cast<double>(n)), 8.0, 32.0));
    const int block = rhs_block_columns(n, most);
    for (int j0 = 0; j0 < m; j0 += block) {
      const int nb = std::min(block, m - j0);
      const Eigen::MatrixXd Yb = factor_->forward(transposed_rows(B(), rows(), j0, nb));
      for (int j = 0; j < nb; ++j) {
        for (Eigen::Index i = 0; i < Yb.rows(); ++i)
          if (Yb(i, j) != 0) {
            inner.push_back(static_cast<int>(i));
            values.push_back(Yb(i, j));
          }
        outer.push_back(static_cast<int>(values.size()));
      }
      if (12.0 * static_cast<double>(values.size()) > setup_bytes) return dual_matrix_from_solves(0);
    }
    SparseMatrix Y = Eigen::Map<const SparseMatrix>(n, m, static_cast<Eigen::Index>(values.size()), outer.data(),
                                                    inner.data(), values.data());
    std::vector<int>().swap(inner);
    std::vector<double>().swap(values);
    Eigen::MatrixXd S = gram(Y);  // (its row-wise copy of Y: la/memory_estimate.cpp counts Y twice)
    if (max_cached_share > 0 && 12.0 * static_cast<double>(Y.nonZeros()) <= kept_bytes) Y_ = std::move(Y);
    return S;
  }

  /// S = N K⁻¹Nᵀ as the backend's Schur complement where it has one cheaper than m solves (MUMPS:
  /// one factorization of [K Nᵀ; N 0], which sums a row's entries given by several ranks, its pieces';
  /// a step then takes two solves), else by block solves.
  Eigen::MatrixXd dual_matrix_from_schur_or_solves(double max_cached_share) {
    if (std::optional<Eigen::MatrixXd> S = factor_->schur_complement(B(), rows(), unknowns())) {
      schur_ = true;
      return std::move(*S);
    }
    return dual_matrix_from_solves(max_cached_share);
  }

  /// S = N K⁻¹Nᵀ by block solves X = K⁻¹Nᵀ (collective: every rank solves the same
  /// blocks; Nᵀ's columns from each row's owner and pieces); S's rows are computed where
  /// N's rows and pieces live, then summed over the ranks (one owner per row: exact; with
  /// pieces their partial rows added, the same S everywhere for a given partition). X is
  /// kept as W when it fits on every rank (a step is then one solve: u = u_free − Wλ).
  Eigen::MatrixXd dual_matrix_from_solves(double max_cached_share) {
    const int m = unknowns();
    const auto n_owned = c_.N.cols();
    double max_bytes = max_cached_share > 0 ? kMaxCachedBytes : 0;
    if (factor_->factor_bytes() > 0) max_bytes = std::min(max_bytes, max_cached_share * factor_->factor_bytes());
    const bool keep_w = !factor_->has_halves() &&
                        comm().max(static_cast<double>(n_owned) * m * sizeof(double)) <= max_bytes;
    if (keep_w) W_.resize(n_owned, m);
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(m, m);
    const int block = factor_->has_halves() ? rhs_block_columns(n_owned) : common_block_columns(comm(), n_owned, 64);
    for (int j0 = 0; j0 < m; j0 += block) {
      const int nb = std::min(block, m - j0);
      const Eigen::MatrixXd X = factor_->solve(transposed_rows(B(), rows(), j0, nb));
      if (keep_w) W_.middleCols(j0, nb) = X;
      const Eigen::MatrixXd NX = B() * X;
      for (size_t k = 0; k < rows().size(); ++k) S.block(rows()[k], j0, 1, nb) = NX.row(static_cast<Eigen::Index>(k));
    }
    comm().sum(S.data(), m * m);
    return S;
  }

  std::shared_ptr<const la::SpdOperator> K_;  // for the reported residuals
  ContactConstraints c_;
  std::shared_ptr<const la::LinearSolver> factor_;
  std::vector<const ContactLaw*> row_laws_;  // every row's law (replicated); empty: Signorini
  std::vector<const FrictionLaw*> row_frictions_;  // every row's friction law (replicated; nullptr: none)
  Vector compliance_;                        // every row's 1/k_i (replicated; 0: rigid), with row_laws_
  Vector lower_;                             // every row's λ_i ≥ lower_i (replicated), with row_laws_
  bool nonlinear_ = false;                   // some row's law is not linear
  Vector bond_length_;                       // every row's bond length (replicated) where some row has one, else empty
  SparseMatrix B_;              // N, or with friction [N; T], in λ's order, then the pieces (block_rows)
  std::vector<int> B_rows_;     // its rows' places in λ
  std::unique_ptr<DualProblem> problem_;  // the step's dual (dual_problem), with its S
  SparseMatrix Y_;     // L⁻¹PNᵀ (factors with halves), or empty
  Eigen::MatrixXd W_;  // K⁻¹Nᵀ on the owned rows (factors without halves), or empty
  bool schur_ = false;  // S came from the backend's Schur complement (no W)
  static constexpr double kMaxCachedBytes = 256.0 * 1024 * 1024;
};

}  // namespace

std::unique_ptr<ContactSolver> make_dual_active_set_solver(std::shared_ptr<const la::SpdOperator> K,
                                                           std::shared_ptr<const la::LinearSolver> factor,
                                                           ContactConstraints constraints, double max_cached_share) {
  return std::make_unique<ActiveSetContactSolver>(std::move(K), std::move(factor), std::move(constraints),
                                                  max_cached_share);
}

}  // namespace vpc

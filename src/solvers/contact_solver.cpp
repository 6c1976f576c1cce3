#include "solvers/contact_solver.hpp"

#include "solvers/contact_capabilities.hpp"

#include "core/error.hpp"
#include "la/backend.hpp"
#include "solvers/dual_active_set.hpp"
#include "solvers/penalty_duality_contact.hpp"
#include "solvers/primal_active_set.hpp"
#include "solvers/solver_failure.hpp"
#include "solvers/stick_slip.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace vpc {

/// λ's entries (m numbers) at this rank's constraint rows.
Vector local_rows(const ContactConstraints& c, const Vector& lambda) {
  Vector l(static_cast<Eigen::Index>(c.rows.size()));
  for (size_t k = 0; k < c.rows.size(); ++k) l[static_cast<Eigen::Index>(k)] = lambda[c.rows[k]];
  return l;
}

double ContactResiduals::max() const {
  return std::max({equilibrium, penetration, negative_force, complementarity, friction_bound, stick_slip, slip_direction});
}

Vector local_normal(const ContactConstraints& c, const Vector& lambda) {
  Vector l(static_cast<Eigen::Index>(c.rows.size()));
  for (size_t k = 0; k < c.rows.size(); ++k) l[static_cast<Eigen::Index>(k)] = lambda[c.rows[k] * c.block];
  return l;
}

Vector local_tangential(const ContactConstraints& c, const Vector& lambda) {
  const int t = c.block - 1;
  Vector l(static_cast<Eigen::Index>(c.rows.size()) * t);
  for (size_t k = 0; k < c.rows.size(); ++k)
    for (int j = 0; j < t; ++j) l[static_cast<Eigen::Index>(k) * t + j] = lambda[c.rows[k] * c.block + 1 + j];
  return l;
}

Vector replicate_blocks(const la::Comm& comm, const ContactConstraints& c, const Vector& normal, const Vector& tangential) {
  const int b = c.block, t = b - 1;
  Vector all = Vector::Zero(static_cast<Eigen::Index>(c.m) * b);
  for (size_t k = 0; k < c.rows.size(); ++k) {
    const auto e = static_cast<Eigen::Index>(k);
    all[c.rows[k] * b] = normal[e];
    for (int j = 0; j < t; ++j) all[c.rows[k] * b + 1 + j] = tangential[e * t + j];
  }
  comm.sum(all.data(), all.size());
  return all;
}

void set_friction_data(ContactConstraints& c, const Vector& tresca, const Vector& shift) {
  const auto rows = static_cast<Eigen::Index>(c.rows.size());
  require(c.frictional(), "internal: friction data for frictionless contact constraints");
  require(tresca.size() == rows && shift.size() == rows * (c.block - 1),
          "internal: {} friction bounds and {} slip shifts for {} contact rows of {} tangents", tresca.size(),
          shift.size(), rows, c.block - 1);
  require(tresca.allFinite() && shift.allFinite() && (tresca.size() == 0 || tresca.minCoeff() >= 0),
          "internal: friction bounds must be finite and >= 0 and slip shifts finite");
  c.tresca = tresca;
  c.shift = shift;
}

void set_bond_data(ContactConstraints& c, const StepBonds& bonds) {
  const Vector& bond = bonds.normal;
  const auto rows = static_cast<Eigen::Index>(c.rows.size());
  require(c.bond_length.size() == rows && bond.size() == rows, "internal: {} bonds for {} contact rows ({} bond lengths)",
          bond.size(), rows, c.bond_length.size());
  for (Eigen::Index i = 0; i < rows; ++i)
    require(std::isfinite(bond[i]) && bond[i] >= 0 && (bond[i] == 0 || c.bond_length[i] > 0),
            "internal: a bond must be finite and >= 0, and 0 on a row without a bond length; row {}: {} (length {})", i,
            bond[i], c.bond_length[i]);
  c.bond = bond;
  if (bonds.shear.size() == 0 && bonds.stretch.size() == 0) return;
  require(c.frictional() && bonds.shear.size() == rows && bonds.stretch.size() == rows * (c.block - 1),
          "internal: {} tangential bonds and {} stretches for {} contact rows of {} tangents", bonds.shear.size(),
          bonds.stretch.size(), rows, c.block - 1);
  require(bonds.stretch.allFinite() && (rows == 0 || (bonds.shear.allFinite() && bonds.shear.minCoeff() >= 0)),
          "internal: tangential bonds must be finite and >= 0, their stretches finite");
  c.shear_bond = bonds.shear;
  c.bond_stretch = bonds.stretch;
}

Vector shear_bond_force(const ContactConstraints& c, Eigen::Index i, Eigen::Ref<const Vector> slip) {
  const double a = c.shear_bond_of(i);
  if (!(a > 0)) return Vector::Zero(slip.size());
  const auto t = static_cast<Eigen::Index>(c.block - 1);
  const Vector v = slip + c.bond_stretch.segment(i * t, t);
  const double size = v.norm(), L = c.bond_length_of(i);
  return size <= L ? Vector(a * v) : Vector(a * L / size * v);
}

ContactStatus contact_status(double lambda_nu, double tangential_norm, double bound, double slack) {
  if (!(lambda_nu > 0)) return ContactStatus::Free;
  return tangential_norm >= std::min((1 - kSlipShare) * bound, bound - slack) ? ContactStatus::Slip : ContactStatus::Stick;
}

ContactResiduals contact_residuals(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F,
                                   const Vector& u, const Vector& lambda) {
  const la::Comm& comm = K.comm();
  ContactResiduals r;
  if (!comm.all(F.allFinite() && u.allFinite() && c.gap.allFinite()) || !lambda.allFinite()) {
    const double inf = std::numeric_limits<double>::infinity();  // NaN would compare as "small"
    return {inf, inf, inf, inf, inf, inf, inf};
  }
  Vector Ku;
  K.mult_threaded(u, Ku);
  const Vector lambda_local = local_normal(c, lambda);
  Vector s = gap_left(comm, c, u);  // the gap left: ≥ 0, plus the penetration a compliant law gives at λ
  const Vector s0 = s;  // the separation (adhesion's bonds read it)
  for (Eigen::Index i = 0; i < s.size() && !c.laws.empty(); ++i)
    if (const ContactLaw& law = c.law_of(i); !law.rigid()) s[i] = law.gap_left(s[i], lambda_local[i], c.compliance_of(i));
  auto inf = [&](const Vector& v) { return comm.max(v.size() ? v.cwiseAbs().maxCoeff() : 0.0); };
  const double f_scale = std::max({inf(F), inf(Ku), 1e-300});
  Vector stationarity = Ku - F + c.N.transpose() * lambda_local;
  const Vector tangential = local_tangential(c, lambda);  // rows × (b − 1): none without friction
  stationarity.head(c.T.cols()) += c.T.transpose() * tangential;
  add_piece_loads(c, lambda, stationarity);
  r.equilibrium = inf(stationarity) / f_scale;
  const double l_scale = std::max({lambda.size() ? lambda.cwiseAbs().maxCoeff() : 0.0, f_scale});
  // Not max(‖u‖, ‖g‖) alone: where every free dof is held by contact at a zero gap the exact
  // u is 0, and the dual solver's u = K⁻¹(F − Nᵀλ) is 0 only to round-off (~1e-17), which
  // that scale measured against itself: penetration and complementarity ~1 (issue 26). The
  // displacement l_scale / max K_ii is below any u the forces make otherwise, so elsewhere
  // the scale, and so every residual, is what it was.
  const Vector K_diag = K.diagonal();
  const double k_max = comm.max(K_diag.size() ? K_diag.maxCoeff() : 0.0);
  const double u_scale = std::max({inf(u), inf(c.gap), k_max > 0 ? l_scale / k_max : 0.0, 1e-300});
  for (int i = 0; i < s.size(); ++i) {  // against the row's dual bound: (λ − lower) ⟂ s ≥ 0
    const double above = lambda_local[i] - c.lower_of(i);
    if (lambda_local[i] < 0 && c.bond_of(i) > 0) {  // a bond that pulls: s0 ≥ 0 and λ its force there
      r.penetration = std::max(r.penetration, -s0[i] / u_scale);
      r.negative_force = std::max(r.negative_force, -above / l_scale);
      r.complementarity = std::max(r.complementarity, std::abs(lambda_local[i] - c.bond_force(i, s0[i])) / l_scale);
      continue;
    }
    r.penetration = std::max(r.penetration, -s[i] / u_scale);
    r.negative_force = std::max(r.negative_force, -above / l_scale);
    // (the product measured against its factors' scales: a bond's tension bound −a_i far below the forces
    // (above ≫ l_scale) would otherwise multiply the gap's round-off by a_i / l_scale; for Signorini's
    // rows, above = λ ≤ l_scale, and this is λ s / (l_scale u_scale) as before)
    r.complementarity = std::max(r.complementarity, std::abs(above * s[i]) / (std::max(std::abs(above), l_scale) * u_scale));
  }
  // SPEC §7 over each row's b − 1 tangents: |λ_τ|_C ≤ s; below it Δ = 0; at it Δ in C_s's normal
  // cone. Without friction a row has no tangents and its bound is 0: each of these is 0 there.
  const int t = c.block - 1;
  const Vector slip = slip_increment(comm, c, u);
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    const auto l = tangential.segment(i * t, t);
    const auto d = slip.segment(i * t, t);
    if (c.shear_bond_of(i) > 0) {  // a tangential bond: its force is a function of the stretch, as a compliant row's
      // (measured as a force: its slip Δ + v − λ_τ/a_τ would multiply λ_τ's round-off by 1/a_τ where α → 0)
      r.friction_bound = std::max(r.friction_bound, (l.norm() - c.bound(i, lambda_local[i])) / l_scale);
      r.stick_slip = std::max(r.stick_slip, (l - shear_bond_force(c, i, d)).norm() / l_scale);
      continue;
    }
    const FrictionLaw& law = c.friction_of(i);
    const double bound = c.bound(i, lambda_local[i]), ln = law.gauge(l.data(), t), dn = d.norm();
    r.friction_bound = std::max(r.friction_bound, (ln - bound) / l_scale);
    // Below the bound a node's slip is measured against the displacement scale, weighted by how far
    // below it is up to the force scale: a bound far above every force (μ or a Tresca bound of 1e8:
    // a stuck face) would otherwise multiply a sticking node's round-off slip into a failure.
    r.stick_slip = std::max(r.stick_slip, std::clamp(bound - ln, 0.0, l_scale) * dn / (l_scale * u_scale));
    // λ_τ·Δ ≤ |λ_τ|_C |Δ|_C*, equal where Δ lies in the set's normal cone at λ_τ (along λ_τ on a disc).
    r.slip_direction = std::max(r.slip_direction, (ln * law.dual_gauge(d.data(), t) - l.dot(d)) / (l_scale * u_scale));
  }
  r.force_scale = l_scale;  // the same on every rank (λ is replicated, f_scale reduced)
  for (double* x : {&r.penetration, &r.negative_force, &r.complementarity, &r.friction_bound, &r.stick_slip,
                    &r.slip_direction})
    *x = comm.max(*x);
  return r;
}

std::string contact_failure(const ContactReport& r, double tolerance) {
  if (r.pulled_off)
    return fmt::format("found no equilibrium: the load on a body its bonds alone hold exceeds what its contact rows "
                       "can balance ({:.3g} of it unbalanced: each bond pulls at most gamma_nu alpha^2 L |Gamma_3|_i)",
                       r.pull_off_excess);
  const ContactResiduals& x = r.residuals;
  if (std::isinf(x.max()) || std::isnan(x.max())) return kSolverMetNonFinite;
  std::vector<std::string> above;
  const std::tuple<const char*, const char*, double> named[] = {
      {"equilibrium", "KKT stationarity: Ku = F - N^T lambda", x.equilibrium},
      {"penetration", "feasibility: Nu <= g", x.penetration},
      {"negative-force", "feasibility: lambda >= 0", x.negative_force},
      {"complementarity", "lambda_i (g - Nu)_i = 0", x.complementarity},
      {"friction-bound", "|lambda_t| <= its bound", x.friction_bound},
      {"stick-slip", "no slip below the bound", x.stick_slip},
      {"slip-direction", "slip along the tangential force", x.slip_direction}};
  for (const auto& [name, meaning, value] : named)
    if (!(value <= tolerance)) above.push_back(fmt::format("{} residual {:.2e} ({})", name, value, meaning));
  return solver_failure(r.converged, r.iterations,
                        above.empty() ? "" : fmt::format("{} above the tolerance {:.1e}", fmt::join(above, ", "), tolerance));
}

namespace {

/// What every report has: the solve's outcome and its residuals.
ContactReport solve_report(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F, const Vector& u,
                           const Vector& lambda, bool converged, int iterations, double active_threshold) {
  ContactReport rep;
  rep.converged = converged;
  rep.iterations = iterations;
  rep.active_threshold = active_threshold;
  rep.residuals = contact_residuals(K, c, F, u, lambda);
  return rep;
}

}  // namespace

ContactReport contact_report(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F, const Vector& u,
                             const Vector& lambda, bool converged, int iterations, double active_threshold) {
  require(lambda.size() == c.m, "internal: a report of {} normal forces for {} contact rows", lambda.size(), c.m);
  ContactReport rep = solve_report(K, c, F, u, lambda, converged, iterations, active_threshold);
  rep.n_active = static_cast<int>((lambda.array() > active_threshold).count());
  rep.total_force = lambda.sum();
  return rep;
}

ContactReport friction_report(const la::SpdOperator& K, const ContactConstraints& c, const Vector& F, const Vector& u,
                              const Vector& lambda, bool converged, int iterations, double active_threshold) {
  ContactReport rep = solve_report(K, c, F, u, lambda, converged, iterations, active_threshold);
  const int b = c.block, t = b - 1;
  for (int i = 0; i < c.m; ++i) {
    rep.n_active += lambda[i * b] > active_threshold;
    rep.total_force += lambda[i * b];
  }
  // Stick and slip counts and the dissipation from this rank's rows.
  const std::vector<ContactStatus> status = stick_slip(c, lambda, kSlipForceShare * rep.residuals.force_scale, active_threshold);
  const Vector tangential = local_tangential(c, lambda), slip = slip_increment(K.comm(), c, u);
  double sums[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < status.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    sums[0] += status[i] == ContactStatus::Stick;
    sums[1] += status[i] == ContactStatus::Slip;
    sums[2] += tangential.segment(k * t, t).dot(slip.segment(k * t, t));
    sums[3] += status[i] == ContactStatus::Open;
  }
  K.comm().sum(sums, 4);
  rep.n_stick = static_cast<int>(sums[0]);
  rep.n_slip = static_cast<int>(sums[1]);
  rep.dissipation = sums[2];
  rep.n_open = static_cast<int>(sums[3]);
  return rep;
}

/// m numbers, the same on every rank, from this rank's rows' values (one owner per row: the sum is exact).
Vector replicate(const la::Comm& comm, const ContactConstraints& c, const Vector& local) {
  Vector all = Vector::Zero(c.m);
  for (size_t k = 0; k < c.rows.size(); ++k) all[c.rows[k]] = local[static_cast<Eigen::Index>(k)];
  comm.sum(all.data(), c.m);
  return all;
}

const Vector& checked_gap(const ContactConstraints& c, const Vector& gap) {
  require(gap.size() == static_cast<Eigen::Index>(c.rows.size()), "internal: {} gaps for {} contact rows", gap.size(),
          c.rows.size());
  return gap;
}

Eigen::MatrixXd transposed_rows(const SparseMatrix& N, const std::vector<int>& rows, int j0, int nb) {
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(N.cols(), nb);
  const SparseMatrix Nt = N.transpose();
  for (int k = 0; k < Nt.outerSize(); ++k) {
    const int j = rows[k] - j0;
    if (j < 0 || j >= nb) continue;
    for (SparseMatrix::InnerIterator it(Nt, k); it; ++it) B(it.row(), j) = it.value();
  }
  return B;
}

double friction_force_tolerance(double residual_tolerance) { return std::max(1e-1 * residual_tolerance, 1e-12); }

std::unique_ptr<ContactSolver> make_contact_solver(const std::string& name, std::shared_ptr<const la::SpdOperator> K,
                                                   std::shared_ptr<const la::LinearSolver> K_factor,
                                                   ContactConstraints constraints, const la::LinearSolverFactory& make_factor,
                                                   const ContactSolverOptions& opt) {
  require(K != nullptr, "contact solver: no stiffness matrix");
  require(constraints.m > 0, "contact solver: there are no contact unknowns (is the contact part empty?)");
  require(K_factor != nullptr, "contact solver: needs the factor of K");
  const auto rows = static_cast<Eigen::Index>(constraints.rows.size());
  require(constraints.N.rows() == rows && constraints.gap.size() == rows && constraints.N.cols() == K->n_owned(),
          "internal: contact constraints of {} rows x {} columns for {} rows, {} gaps and {} owned dofs",
          constraints.N.rows(), constraints.N.cols(), rows, constraints.gap.size(), K->n_owned());
  require(constraints.laws.empty() ||
              (constraints.datum.size() == rows && constraints.law.size() == constraints.rows.size()),
          "internal: {} law data and {} laws for {} contact rows", constraints.datum.size(),
          constraints.law.size(), rows);
  refuse_unsolvable(name, contact_needs(K->comm(), constraints));
  if (name == "active-set")
    return make_dual_active_set_solver(std::move(K), std::move(K_factor), std::move(constraints), opt.max_cached_share);
  if (name == "penalty-duality")
    return make_penalty_duality_contact_solver(std::move(K), *K_factor, std::move(constraints), make_factor, opt);
  if (name == "primal-active-set") {
    require(contact_reflections(constraints.N).size() == 0,
            "internal: the primal contact solver with rows off the axes needs Q K Q (make_primal_active_set_solver)");
    return make_primal_active_set_solver(K, nullptr, std::shared_ptr<la::LinearSolver>(make_factor("K_active")),
                                         std::move(constraints), 0, opt.friction_tolerance);
  }
  fail("unknown contact solver '{}'; expected active-set, primal-active-set or penalty-duality", name);
}

std::unique_ptr<ContactSolver> make_contact_solver(const std::string& name, const SparseMatrix& K,
                                                   const SparseMatrix& N, const Vector& gap,
                                                   const ContactSolverOptions& opt) {
  auto op = std::make_shared<const la::SparseOperator>(K);
  std::shared_ptr<la::LinearSolver> factor = la::serial_backend()->factor("K");
  ContactConstraints c;
  c.m = static_cast<int>(N.rows());
  c.N = N;
  c.gap = gap;
  for (int i = 0; i < c.m; ++i) c.rows.push_back(i);
  if (name == "primal-active-set") {
    const SparseMatrix Q = contact_reflections(N);
    auto K_rot = Q.size() ? std::make_shared<const la::SparseOperator>(SparseMatrix(Q * K * Q)) : nullptr;
    return make_primal_active_set_solver(std::move(op), std::move(K_rot), std::move(factor), std::move(c), 0,
                                         opt.friction_tolerance);
  }
  factor->factorize(*op, "elastic stiffness K");
  return make_contact_solver(name, std::move(op), std::move(factor), std::move(c), la::factor_factory(la::serial_backend()), opt);
}

}  // namespace vpc

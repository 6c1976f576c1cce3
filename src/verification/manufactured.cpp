#include "verification/manufactured.hpp"

#include "core/error.hpp"
#include "mesh/generators.hpp"

#include <fmt/format.h>

#include <cmath>
#include <regex>

namespace vpc {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Sets component (a, b) of a symmetric tensor.
void set_component(SymTensor& s, int a, int b, double v) {
  if (a == b) {
    s[a] = v;
  } else {
    s[3 + (3 - a - b)] = v;
  }
}

/// X = (x, t) with the derivative of coordinate `j` (0..2 space, 3 time) seeded.
std::array<D1, 4> seed(const Point& x, double t, int j) {
  std::array<D1, 4> X;
  for (int i = 0; i < 3; ++i) X[i] = {x[i], i == j ? 1.0 : 0.0};
  X[3] = {t, j == 3 ? 1.0 : 0.0};
  return X;
}

/// X = (x, t) with the inner derivative along j and the outer one along l.
std::array<D2, 4> seed2(const Point& x, double t, int j, int l) {
  std::array<D2, 4> X;
  for (int i = 0; i < 4; ++i) {
    const double xi = i < 3 ? x[i] : t;
    X[i] = {{xi, i == j ? 1.0 : 0.0}, {i == l ? 1.0 : 0.0, 0.0}};
  }
  return X;
}

SymTensor to_tensor(const std::array<double, 6>& z) {
  SymTensor s;
  for (int i = 0; i < 6; ++i) s[i] = z[i];
  return s;
}

}  // namespace

ManufacturedSolution::ManufacturedSolution(int dim, bool with_history, const Elasticity& elasticity, double kappa)
    : dim_(dim), with_history_(with_history), elasticity_(elasticity), kappa_(kappa) {
  require(dim >= 1 && dim <= 3, "manufactured solution: d must be 1, 2 or 3 (got {})", dim);
  require(elasticity.dim() == dim, "manufactured solution: elasticity '{}' is not for d = {}", elasticity.name(), dim);
}

template <typename S>
ManufacturedValues<S> ManufacturedSolution::fields(const std::array<S, 4>& X) const {
  using std::cos, std::sin;
  const S &x = X[0], &y = X[1], &w = X[2], &t = X[3];
  ManufacturedValues<S> f;
  // u = 0 on x = 0; ∇u = 0 on x = 1 (p(1) = p'(1) = 0, q'(1) = 0).
  const S p = x * (1.0 - x) * (1.0 - x);
  const S q = x * (2.0 - x);
  const S a = sin((kPi / 2) * t);
  f.u[0] = a * (0.10 * p * cos((kPi / 2) * y) * cos((kPi / 2) * w) + 0.02 * q);
  if (dim_ >= 2) f.u[1] = a * (0.08 * p * sin(kPi * y) * (1.0 + w) + 0.01 * q);
  if (dim_ == 3) f.u[2] = a * (0.06 * p * (1.0 + y) * sin(kPi * w) + 0.01 * q);
  // z = 0 at t = 0 and on x = 1; in S_d.
  if (with_history_) {
    const S b = 1.0 - cos((kPi / 2) * t);
    const S r = b * (1.0 - x);
    f.z[0] = 0.05 * r * (1.0 + 0.5 * cos(kPi * y));
    if (dim_ >= 2) {
      f.z[1] = 0.04 * r * (1.0 + 0.5 * sin(kPi * (y + w)));
      f.z[5] = 0.03 * r * cos((kPi / 2) * x);
    }
    // Plane strain carries z33 (and σ33) as well, never z13, z23.
    if (dim_ == 3 || elasticity_.kind() == Elasticity::Kind::PlaneStrain) f.z[2] = 0.02 * r * (1.0 + y);
    if (dim_ == 3) {
      f.z[3] = 0.01 * r * sin(kPi * w);
      f.z[4] = 0.015 * r * (1.0 + x);
    }
  }
  // ∂β/∂ν = 0 on every side of the box; 0.3 <= β <= 0.9.
  S c = 0.2 * (1.0 + 0.5 * sin(kPi * t));
  c = c * cos(kPi * x);
  if (dim_ >= 2) c = c * cos(kPi * y);
  if (dim_ == 3) c = c * cos(kPi * w);
  f.beta = 0.6 + c;
  return f;
}

template ManufacturedValues<double> ManufacturedSolution::fields(const std::array<double, 4>&) const;
template ManufacturedValues<D1> ManufacturedSolution::fields(const std::array<D1, 4>&) const;
template ManufacturedValues<D2> ManufacturedSolution::fields(const std::array<D2, 4>&) const;

Point ManufacturedSolution::u(const Point& x, double t) const {
  const auto f = fields<double>({x[0], x[1], x[2], t});
  return {f.u[0], f.u[1], f.u[2]};
}

std::array<Point, 3> ManufacturedSolution::grad_u(const Point& x, double t) const {
  std::array<Point, 3> g{};
  for (int j = 0; j < dim_; ++j) {
    const auto f = fields(seed(x, t, j));
    for (int i = 0; i < dim_; ++i) g[i][j] = f.u[i].d;
  }
  return g;
}

SymTensor ManufacturedSolution::eps(const Point& x, double t) const {
  const auto g = grad_u(x, t);
  SymTensor e;
  for (int a = 0; a < dim_; ++a)
    for (int b = a; b < dim_; ++b) set_component(e, a, b, 0.5 * (g[a][b] + g[b][a]));
  return e;
}

SymTensor ManufacturedSolution::z(const Point& x, double t) const {
  return to_tensor(fields<double>({x[0], x[1], x[2], t}).z);
}

SymTensor ManufacturedSolution::sigma(const Point& x, double t) const {
  return elasticity_.apply(eps(x, t)) + z(x, t);
}

double ManufacturedSolution::beta(const Point& x, double t) const {
  return fields<double>({x[0], x[1], x[2], t}).beta;
}

Point ManufacturedSolution::grad_beta(const Point& x, double t) const {
  Point g{0, 0, 0};
  for (int j = 0; j < dim_; ++j) g[j] = fields(seed(x, t, j)).beta.d;
  return g;
}

ExactSolution::Values ManufacturedSolution::values(const Point& x, double t) const {
  Values v;
  SymTensor z;
  for (int j = 0; j < dim_; ++j) {
    const auto f = fields(seed(x, t, j));
    for (int i = 0; i < dim_; ++i) v.grad_u[i][j] = f.u[i].d;
    v.grad_beta[j] = f.beta.d;
    if (j == 0) {
      for (int i = 0; i < 3; ++i) v.u[i] = f.u[i].v;
      for (int c = 0; c < 6; ++c) z[c] = f.z[c].v;
      v.beta = f.beta.v;
    }
  }
  SymTensor e;
  for (int a = 0; a < dim_; ++a)
    for (int b = a; b < dim_; ++b) set_component(e, a, b, 0.5 * (v.grad_u[a][b] + v.grad_u[b][a]));
  v.sigma = elasticity_.apply(e) + z;
  return v;
}

SymTensor ManufacturedSolution::z_dot(const Point& x, double t) const {
  const auto f = fields(seed(x, t, 3));
  SymTensor s;
  for (int i = 0; i < 6; ++i) s[i] = f.z[i].d;
  return s;
}

double ManufacturedSolution::beta_dot(const Point& x, double t) const { return fields(seed(x, t, 3)).beta.d; }

double ManufacturedSolution::laplacian_beta(const Point& x, double t) const {
  double s = 0;
  for (int j = 0; j < dim_; ++j) s += fields(seed2(x, t, j, j)).beta.d.d;
  return s;
}

Point ManufacturedSolution::body_force(const Point& x, double t) const {
  const int d = dim_;
  // H[i][j][l] = ∂_j ∂_l u_i.
  double H[3][3][3] = {};
  SymTensor dz[3];  // ∂_j z, from the inner derivative of the (j, j) evaluation
  for (int j = 0; j < d; ++j)
    for (int l = j; l < d; ++l) {
      const auto f = fields(seed2(x, t, j, l));
      for (int i = 0; i < d; ++i) H[i][j][l] = H[i][l][j] = f.u[i].d.d;
      if (l == j)
        for (int c = 0; c < 6; ++c) dz[j][c] = f.z[c].v.d;
    }
  Point f0{0, 0, 0};
  // (Div ℰε(u))_i = Σ_j (ℰ ∂_j ε(u))_ij, ℰ being linear and constant.
  for (int j = 0; j < d; ++j) {
    SymTensor de;
    for (int a = 0; a < d; ++a)
      for (int b = a; b < d; ++b) set_component(de, a, b, 0.5 * (H[a][j][b] + H[b][j][a]));
    const SymTensor s = elasticity_.apply(de);
    for (int i = 0; i < d; ++i) f0[i] -= s(i, j);
  }
  // (Div z)_i = Σ_j ∂_j z_ij.
  for (int j = 0; j < d; ++j)
    for (int i = 0; i < d; ++i) f0[i] -= dz[j](i, j);
  return f0;
}

Point ManufacturedSolution::traction(const Point& x, double t) const {
  Point n{0, 0, 0};
  for (int j = 0; j < dim_; ++j) {
    if (std::abs(x[j]) < 1e-9) n[j] = -1;
    if (std::abs(x[j] - 1) < 1e-9) n[j] = 1;
  }
  const SymTensor s = sigma(x, t);
  Point f{0, 0, 0};
  for (int i = 0; i < dim_; ++i)
    for (int j = 0; j < dim_; ++j) f[i] += s(i, j) * n[j];
  return f;
}

PointState ManufacturedSolution::exact_state(const Point& x, double t) const {
  PointState s;
  s.eps = eps(x, t);
  s.sigma = elasticity_.apply(s.eps) + z(x, t);
  s.beta = beta(x, t);
  s.dim = elasticity_.stress_dim();
  s.x = x;
  s.t = t;
  return s;
}

// ---------------------------------------------------------------------------

ManufacturedLaw::ManufacturedLaw(std::shared_ptr<const ViscoplasticLaw> base,
                                 std::shared_ptr<const ManufacturedSolution> exact, ManufacturedForcing forcing,
                                 double k)
    : base_(std::move(base)), exact_(std::move(exact)), forcing_(forcing), k_(k) {}

SymTensor ManufacturedLaw::forcing(const Point& x, double t) const {
  const SymTensor g = base_->rate(exact_->exact_state(x, t));
  if (forcing_ == ManufacturedForcing::Continuous) return exact_->z_dot(x, t) - g;
  return (1.0 / k_) * (exact_->z(x, t + k_) - exact_->z(x, t)) - g;
}

SymTensor ManufacturedLaw::rate(const PointState& s) const { return base_->rate(s) + forcing(s.x, s.t); }

std::string ManufacturedLaw::describe() const {
  return fmt::format("{} + manufactured history source ({})", base_->describe(), to_string(forcing_));
}

ManufacturedSource::ManufacturedSource(std::shared_ptr<const DamageSource> base,
                                       std::shared_ptr<const ManufacturedSolution> exact, ManufacturedForcing forcing,
                                       double k)
    : base_(std::move(base)), exact_(std::move(exact)), forcing_(forcing), k_(k) {}

double ManufacturedSource::forcing(const Point& x, double t) const {
  const double phi = base_->rate(exact_->exact_state(x, t));
  const double kappa = exact_->kappa();
  if (forcing_ == ManufacturedForcing::Continuous)
    return exact_->beta_dot(x, t) - kappa * exact_->laplacian_beta(x, t) - phi;
  return (exact_->beta(x, t + k_) - exact_->beta(x, t)) / k_ - kappa * exact_->laplacian_beta(x, t + k_) - phi;
}

double ManufacturedSource::rate(const PointState& s) const { return base_->rate(s) + forcing(s.x, s.t); }

std::string ManufacturedSource::describe() const {
  return fmt::format("{} + manufactured damage source ({})", base_->describe(), to_string(forcing_));
}

// ---------------------------------------------------------------------------

Mesh manufactured_base_mesh(const ManufacturedOptions& o) {
  require(o.cells >= 1, "manufactured case: cells per edge must be >= 1 (got {})", o.cells);
  switch (o.dim) {
    case 1: return make_interval(0, 1, o.cells);
    case 2: return make_rectangle({0, 0, 0}, {1, 1, 0}, o.cells, o.cells);
    case 3: return make_box({0, 0, 0}, {1, 1, 1}, o.cells, o.cells, o.cells);
    default: fail("manufactured case: d must be 1, 2 or 3 (got {})", o.dim);
  }
}

ManufacturedCase make_manufactured_case(const ManufacturedOptions& o, const Mesh& mesh, int n_steps) {
  const int d = o.dim;
  require(mesh.dim() == d, "manufactured case: the mesh has d = {} but the case is for d = {}", mesh.dim(), d);
  require(!o.plane_strain || d == 2, "manufactured case: plane strain is for d = 2 (got d = {})", d);
  const Elasticity elasticity = d == 1   ? Elasticity(Elasticity::Kind::Uniaxial, 1.0, 0.0)
                                : d == 3 ? Elasticity(Elasticity::Kind::Isotropic, 1.0, 0.3)
                                : o.plane_strain ? Elasticity(Elasticity::Kind::PlaneStrain, 1.0, 0.3)
                                                 : Elasticity(Elasticity::Kind::PlaneStress, 1.0, 0.3);
  std::shared_ptr<const ViscoplasticLaw> base_law;
  if (o.law == "elastic") {
    base_law = make_viscoplastic_law("elastic", {});
  } else if (o.law == "maxwell-damage") {
    base_law = make_viscoplastic_law("maxwell-damage", {});
  } else if (o.law == "perzyna" || o.law == "perzyna-von-mises") {
    base_law = make_viscoplastic_law(o.law, {{"E", 1.0}, {"lambda", 1.0}, {"sigma_y", 0.05}});
  } else {
    fail("manufactured case: unknown law '{}'; expected elastic, maxwell-damage, perzyna or perzyna-von-mises", o.law);
  }
  require(o.source == "strain" || o.source == "zero",
          "manufactured case: unknown damage source '{}'; expected strain or zero", o.source);
  std::shared_ptr<const DamageSource> base_source =
      o.source == "strain" ? make_damage_source("strain", {{"c", 2.0}}) : make_damage_source("zero", {});

  ManufacturedCase out;
  auto exact = std::make_shared<const ManufacturedSolution>(d, o.law != "elastic", elasticity, o.kappa);
  out.exact = exact;
  auto p = std::make_shared<Problem>();
  p->name = fmt::format("mms-{}-{}d{}", o.law == "maxwell-damage" ? "maxwell" : o.law, d,
                        o.plane_strain ? "-plane-strain" : "");
  p->mesh = mesh;
  p->clamped = {"left"};
  p->contact.parts = {"right"};
  p->contact.gap = [](const Point&, double) { return 0.5; };
  p->elasticity = elasticity;
  p->kappa = o.kappa;
  p->final_time = o.final_time;
  p->n_steps = n_steps;
  const double k = p->step();
  p->law = std::make_shared<ManufacturedLaw>(base_law, exact, o.forcing, k);
  p->source = std::make_shared<ManufacturedSource>(base_source, exact, o.forcing, k);
  p->f0 = [exact](const Point& x, double t) { return exact->body_force(x, t); };
  p->f2 = [exact](const Point& x, double t) { return exact->traction(x, t); };
  p->beta0 = [exact](const Point& x, double) { return exact->beta(x, 0.0); };
  out.problem = p;
  return out;
}

bool is_manufactured_case_name(const std::string& name) { return name.rfind("mms-", 0) == 0; }

ManufacturedOptions manufactured_options_from_name(const std::string& name) {
  static const std::regex re("mms-(elastic|maxwell|perzyna|perzyna-von-mises)-(([123])d|2d-plane-strain)");
  std::smatch m;
  require(std::regex_match(name, m, re),
          "unknown manufactured case '{}'; expected mms-LAW-Dd with LAW one of elastic, maxwell, perzyna, "
          "perzyna-von-mises and D = 1, 2, 3, or mms-LAW-2d-plane-strain (e.g. mms-maxwell-2d)",
          name);
  ManufacturedOptions o;
  o.law = m[1] == "maxwell" ? "maxwell-damage" : std::string(m[1]);
  o.plane_strain = m[2] == "2d-plane-strain";
  o.dim = o.plane_strain ? 2 : std::stoi(m[3]);
  return o;
}

ManufacturedForcing manufactured_forcing_from_name(const std::string& name) {
  if (name == "continuous") return ManufacturedForcing::Continuous;
  if (name == "discrete") return ManufacturedForcing::Discrete;
  fail("unknown manufactured forcing '{}'; expected continuous or discrete", name);
}

std::string to_string(ManufacturedForcing f) {
  return f == ManufacturedForcing::Continuous ? "continuous" : "discrete";
}

}  // namespace vpc

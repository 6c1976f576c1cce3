// The friction laws (SPEC §7) and their registry: one line per law.
#include "contact/friction_law.hpp"

#include "core/error.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace vpc {

LawField nonnegative_field(FrictionKeys& keys, const std::string& key, bool time, const std::string& what,
                           std::string& text) {
  if (!keys.has(key)) fail("{}: missing key {} ({}: a number or a formula)", keys.where(key), key, what);
  LawField f = keys.field(key, time);
  if (!keys.is_number(key)) {
    text = "(a formula)";
    return f;
  }
  const double v = f(Point{0, 0, 0}, 0.0);
  if (!(v >= 0) || !std::isfinite(v)) fail("{}: expected {} >= 0, got {}", keys.where(key), what, v);
  text = fmt::format("{}", v);
  return f;
}

namespace {

void refuse_keys_of_others(FrictionKeys& keys, const std::string& law) {
  const std::vector<std::string> mine = friction_law_keys(law);
  for (const std::string& k : friction_keys())
    if (std::find(mine.begin(), mine.end(), k) == mine.end() && keys.has(k))
      fail("{}: {} does not belong to friction = \"{}\"", keys.where(k), k, law);
}

template <typename T>
FrictionLawFactory entry() {
  return [](FrictionKeys& keys) -> std::shared_ptr<const FrictionLaw> { return std::make_shared<const T>(keys); };
}

std::vector<std::pair<std::string, FrictionLawFactory>>& table() {
  static std::vector<std::pair<std::string, FrictionLawFactory>> t = {
      {"none", [](FrictionKeys& keys) -> std::shared_ptr<const FrictionLaw> {
         refuse_keys_of_others(keys, "none");
         return nullptr;
       }},
      {"coulomb", entry<CoulombFriction>()},
      {"tresca", entry<TrescaFriction>()},
  };
  return t;
}

}  // namespace

CoulombFriction::CoulombFriction(FrictionKeys& keys) {
  refuse_keys_of_others(keys, "coulomb");
  mu_ = nonnegative_field(keys, "mu", false, "a friction coefficient mu", text_);
  if (!keys.has("shear_limit")) return;
  limit_ = keys.field("shear_limit", false);
  if (!keys.is_number("shear_limit")) {
    text_ += ", shear limit (a formula)";
    return;
  }
  // > 0: a zero limit is no friction at all (friction = "none" says that); +∞ is no limit (leave it out).
  const double v = limit_(Point{0, 0, 0}, 0.0);
  if (!(v > 0) || !std::isfinite(v))
    fail("{}: expected a shear limit > 0 (a traction, the largest tangential traction), got {}",
         keys.where("shear_limit"), v);
  text_ += fmt::format(", shear limit {}", v);
}

CoulombFriction::CoulombFriction(double mu) : mu_([mu](const Point&, double) { return mu; }), text_(fmt::format("{}", mu)) {
  require(mu >= 0 && std::isfinite(mu), "a friction coefficient mu >= 0, got {}", mu);
}

TrescaFriction::TrescaFriction(FrictionKeys& keys) {
  refuse_keys_of_others(keys, "tresca");
  g_ = nonnegative_field(keys, "friction_bound", true, "a friction bound (a traction)", text_);
  moves_ = keys.uses_time("friction_bound");
}

TrescaFriction::TrescaFriction(double bound)
    : g_([bound](const Point&, double) { return bound; }), text_(fmt::format("{}", bound)) {
  require(bound >= 0 && std::isfinite(bound), "a friction bound >= 0, got {}", bound);
}

double FrictionLaw::gauge(const double* l, int t) const {
  double norm2 = 0;  // in order, as the solvers summed it before the law did
  for (int j = 0; j < t; ++j) norm2 += l[j] * l[j];
  return std::sqrt(norm2);
}

double FrictionLaw::dual_gauge(const double* d, int t) const { return FrictionLaw::gauge(d, t); }

void FrictionLaw::project(const double* z, int t, double r, double* p) const {
  const double norm = FrictionLaw::gauge(z, t);
  for (int j = 0; j < t; ++j) p[j] = r * (z[j] / norm);  // on the circle of radius r, along z
}

void FrictionLaw::project_derivative(const double* z, int t, double s, double* dp_dz, double* dp_ds) const {
  const double norm = FrictionLaw::gauge(z, t);
  for (int j = 0; j < t; ++j) {  // (s/|z|)(I − n nᵀ) and n, n = z/|z|
    const double n_j = z[j] / norm;
    dp_ds[j] = n_j;
    for (int l = 0; l < t; ++l) dp_dz[j * t + l] = s / norm * ((j == l ? 1.0 : 0.0) - n_j * z[l] / norm);
  }
}

const FrictionLaw& disc_friction() {
  static const TrescaFriction none(0.0);
  return none;
}

bool register_friction_law(const std::string& name, FrictionLawFactory make) {
  auto& t = table();
  require(std::none_of(t.begin(), t.end(), [&](const auto& e) { return e.first == name; }),
          "internal: the friction law '{}' is registered twice", name);
  t.emplace_back(name, std::move(make));
  return true;
}

std::vector<std::string> friction_law_names() {
  std::vector<std::string> names;
  for (const auto& [name, make] : table()) names.push_back(name);
  return names;
}

std::vector<std::string> friction_keys() { return {"mu", "shear_limit", "friction_bound"}; }

std::vector<std::string> friction_law_keys(const std::string& name) {
  if (name == "coulomb") return {"mu", "shear_limit"};
  if (name == "tresca") return {"friction_bound"};
  return {};
}

std::shared_ptr<const FrictionLaw> make_friction_law(const std::string& name, FrictionKeys& keys) {
  for (const auto& [n, make] : table())
    if (n == name) return make(keys);
  fail("unknown friction law '{}'; expected one of: {}", name, fmt::join(friction_law_names(), ", "));
}

}  // namespace vpc

#include "core/expression.hpp"

#include "core/error.hpp"
#include "core/quote.hpp"

#include <fmt/ranges.h>
#include <muParser.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <omp.h>
#include <tuple>

namespace vpc {

std::vector<std::string> Expression::variables(Kind kind) {
  switch (kind) {
    case Kind::Space: return {"x", "y", "z"};
    case Kind::SpaceTime: return {"x", "y", "z", "t"};
    default: return {"x", "y", "z", "t", "vm", "tr_sigma", "tr_eps", "eps_eq", "beta"};
  }
}

Expression::Expression(const std::string& text, Kind kind, const std::string& where)
    : text_(text), where_(where), kind_(kind) {
  const int n_slots = std::max(1, omp_get_max_threads());
  for (int k = 0; k < n_slots; ++k) {
    Slot s{std::make_unique<mu::Parser>(), std::make_unique<Vars>()};
    try {
      Vars& v = *s.vars;
      double* vars[] = {&v.x, &v.y, &v.z, &v.t, &v.vm, &v.tr_sigma, &v.tr_eps, &v.eps_eq, &v.beta};
      const auto names = variables(kind);
      for (size_t i = 0; i < names.size(); ++i) s.parser->DefineVar(names[i], vars[i]);
      s.parser->DefineConst("pi", M_PI);
      s.parser->DefineConst("e", M_E);
      s.parser->SetExpr(text);
      (void)s.parser->Eval();  // compiles; reports unknown names and syntax now
    } catch (const mu::Parser::exception_type& e) {
      fail("{}: invalid expression {}: {} Available variables: {}", where, quote_formula(text), printable(e.GetMsg(), 200),
           fmt::join(variables(kind), ", "));
    }
    slots_.push_back(std::move(s));
  }
  const auto used = slots_.front().parser->GetUsedVar();
  uses_position_ = used.count("x") + used.count("y") + used.count("z") > 0;
  uses_time_ = used.count("t") > 0;
}

Expression::~Expression() = default;

Expression::Slot& Expression::slot() const {
  const int t = omp_get_thread_num();
  return const_cast<Slot&>(slots_[t < static_cast<int>(slots_.size()) ? t : 0]);
}

double Expression::eval(Slot& s) const {
  // Evaluation runs inside OpenMP loops, which exceptions must not leave: a
  // formula that cannot be evaluated gives NaN, which the scheme reports.
  double v = std::numeric_limits<double>::quiet_NaN();
  try {
    v = s.parser->Eval();
  } catch (const mu::Parser::exception_type&) {
  }
  if (!std::isfinite(v)) note_not_finite(*s.vars, v);
  return v;
}

void Expression::note_not_finite(const Vars& at, double value) const {
  const std::lock_guard<std::mutex> lock(not_finite_mutex_);
  // The earliest (t, x, y, z): the same evaluation whichever thread met it first.
  auto key = [](const Vars& v) { return std::tuple(v.t, v.x, v.y, v.z); };
  if (!not_finite_ || key(at) < key(not_finite_->first)) not_finite_ = std::pair(at, value);
}

void Expression::check_finite() const {
  const std::lock_guard<std::mutex> lock(not_finite_mutex_);
  if (!not_finite_) return;
  const auto& [v, value] = *not_finite_;
  std::string at;
  if (kind_ == Kind::PointState)
    at = fmt::format(" at the centroid ({:.6g}, {:.6g}, {:.6g}) of a cell, where vm = {:.6g}, tr_sigma = {:.6g}, tr_eps = "
                     "{:.6g}, eps_eq = {:.6g}, beta = {:.6g}",
                     v.x, v.y, v.z, v.vm, v.tr_sigma, v.tr_eps, v.eps_eq, v.beta);
  else if (uses_position_)
    at = fmt::format(" at the point ({}, {}, {})", v.x, v.y, v.z);
  fail("{}: the formula \"{}\" gives {} at t = {:.10g}{}; every value it takes in a run must be a finite number", where_,
       text_, std::isnan(value) ? "NaN" : fmt::format("{}", value), v.t, at);
}

double Expression::operator()(const Point& x, double t) const {
  Slot& s = slot();
  s.vars->x = x[0];
  s.vars->y = x[1];
  s.vars->z = x[2];
  s.vars->t = t;
  return eval(s);
}

double Expression::operator()(const Point& x, double t, const SymTensor& sigma, const SymTensor& eps,
                              double beta) const {
  Slot& s = slot();
  s.vars->vm = sigma.von_mises();
  s.vars->tr_sigma = sigma.trace();
  s.vars->tr_eps = eps.trace();
  const SymTensor d = eps.deviator();
  s.vars->eps_eq = std::sqrt(2.0 / 3.0 * d.dot(d));
  s.vars->beta = beta;
  return (*this)(x, t);
}

}  // namespace vpc

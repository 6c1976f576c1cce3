#include "core/expression.hpp"

#include "core/error.hpp"

#include <fmt/ranges.h>
#include <muParser.h>

#include <cmath>

namespace vpc {

std::vector<std::string> Expression::variables(Kind kind) {
  switch (kind) {
    case Kind::Space: return {"x", "y", "z"};
    case Kind::SpaceTime: return {"x", "y", "z", "t"};
    default: return {"x", "y", "z", "t", "vm", "tr_sigma", "tr_eps", "eps_eq", "beta"};
  }
}

Expression::Expression(const std::string& text, Kind kind, const std::string& where)
    : text_(text), where_(where), parser_(std::make_unique<mu::Parser>()), vars_(std::make_unique<Vars>()) {
  try {
    Vars& v = *vars_;
    double* slots[] = {&v.x, &v.y, &v.z, &v.t, &v.vm, &v.tr_sigma, &v.tr_eps, &v.eps_eq, &v.beta};
    const auto names = variables(kind);
    for (size_t i = 0; i < names.size(); ++i) parser_->DefineVar(names[i], slots[i]);
    parser_->DefineConst("pi", M_PI);
    parser_->DefineConst("e", M_E);
    parser_->SetExpr(text);
    const double probe = parser_->Eval();  // compiles; reports unknown names and syntax now
    (void)probe;
  } catch (const mu::Parser::exception_type& e) {
    fail("{}: invalid expression \"{}\": {} Available variables: {}", where, text, e.GetMsg(),
         fmt::join(variables(kind), ", "));
  }
}

Expression::~Expression() = default;

double Expression::eval() const {
  try {
    return parser_->Eval();
  } catch (const mu::Parser::exception_type& e) {
    fail("{}: cannot evaluate \"{}\": {}", where_, text_, e.GetMsg());
  }
}

double Expression::operator()(const Point& x, double t) const {
  vars_->x = x[0];
  vars_->y = x[1];
  vars_->z = x[2];
  vars_->t = t;
  return eval();
}

double Expression::operator()(const Point& x, double t, const SymTensor& sigma, const SymTensor& eps,
                              double beta) const {
  vars_->vm = sigma.von_mises();
  vars_->tr_sigma = sigma.trace();
  vars_->tr_eps = eps.trace();
  const SymTensor d = eps.deviator();
  vars_->eps_eq = std::sqrt(2.0 / 3.0 * d.dot(d));
  vars_->beta = beta;
  return (*this)(x, t);
}

}  // namespace vpc

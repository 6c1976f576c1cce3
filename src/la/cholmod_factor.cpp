// The serial backend of la::Factor: the CHOLMOD solver of la/cholmod_solver.cpp.
#include "core/error.hpp"
#include "la/factor.hpp"
#include "la/linear_solver.hpp"

namespace vpc::la {

Eigen::MatrixXd Factor::forward(const Eigen::MatrixXd&) const {
  fail("internal: forward half of a factor that has no triangular halves");
}
Eigen::MatrixXd Factor::backward(const Eigen::MatrixXd&) const {
  fail("internal: backward half of a factor that has no triangular halves");
}

namespace {

class CholmodFactor final : public Factor {
 public:
  void factorize(const SpdOperator& A, const char* what) override {
    const auto* s = dynamic_cast<const SparseOperator*>(&A);
    require(s != nullptr, "internal: CHOLMOD factorizes serial operators only ({})", what);
    solver_->factorize(s->matrix(), what);
  }
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const override { x = solver_->solve(b); }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const override { return solver_->solve(B); }
  bool has_halves() const override { return true; }
  Eigen::MatrixXd forward(const Eigen::MatrixXd& B) const override { return solver_->forward(B); }
  Eigen::MatrixXd backward(const Eigen::MatrixXd& Y) const override { return solver_->backward(Y); }
  int n_factorizations() const override { return solver_->n_factorizations(); }
  double factor_bytes() const override { return solver_->factor_bytes(); }

 private:
  std::unique_ptr<LinearSolver> solver_ = make_cholmod_solver();
};

}  // namespace

std::unique_ptr<Factor> make_cholmod_factor(const std::string&) { return std::make_unique<CholmodFactor>(); }

}  // namespace vpc::la

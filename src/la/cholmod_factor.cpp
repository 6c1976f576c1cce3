// The serial backend (la/backend.hpp): Eigen operators and la::Factor by the
// CHOLMOD solver of la/cholmod_solver.cpp.
#include "core/error.hpp"
#include "la/backend.hpp"
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

const Eigen::SparseMatrix<double>& matrix_of(const SpdOperator& A, const char* what) {
  const auto* s = dynamic_cast<const SparseOperator*>(&A);
  require(s != nullptr, "internal: CHOLMOD factorizes serial operators only ({})", what);
  return s->matrix();
}

class CholmodFactor final : public Factor {
 public:
  void factorize(const SpdOperator& A, const char* what) override {
    solver_->factorize(matrix_of(A, what), what);
  }
  std::optional<FactorEstimate> analyze(const SpdOperator& A, const char* what) override {
    return solver_->analyze(matrix_of(A, what), what);
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

namespace vpc::la {

namespace {

class SerialBackend final : public Backend {
 public:
  const Comm& comm() const override { return comm_; }
  std::unique_ptr<SpdOperator> assemble(const Eigen::SparseMatrix<double>& local, const Layout& layout,
                                        int) const override {
    require(layout.comm().serial() && layout.n_ghosts() == 0 && local.rows() == layout.n_owned(),
            "internal: the serial backend assembles one process's matrices");
    return std::make_unique<SparseOperator>(local);
  }
  std::unique_ptr<Factor> factor(const std::string& name) const override { return make_cholmod_factor(name); }
  std::string describe() const override { return "CHOLMOD"; }
  std::string linear_solver() const override { return "cholmod"; }

 private:
  Comm comm_;
};

}  // namespace

std::shared_ptr<const Backend> serial_backend() {
  static const auto backend = std::make_shared<const SerialBackend>();
  return backend;
}

}  // namespace vpc::la

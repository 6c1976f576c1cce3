#pragma once
// A vector over a Layout: its storage is one Eigen::VectorXd, owned entries then
// ghosts, so that the serial code's Eigen expressions work on the owned part
// unchanged; the PETSc backend wraps the same storage (la/petsc.hpp), no copies.
#include "la/layout.hpp"

#include <memory>

namespace vpc::la {

class Vector {
 public:
  Vector() = default;
  explicit Vector(std::shared_ptr<const Layout> layout)
      : layout_(std::move(layout)), values_(Eigen::VectorXd::Zero(layout_->n_local())) {}

  const Layout& layout() const { return *layout_; }
  const std::shared_ptr<const Layout>& layout_ptr() const { return layout_; }
  /// Owned entries, then ghosts.
  Eigen::VectorXd& local() { return values_; }
  const Eigen::VectorXd& local() const { return values_; }
  auto owned() { return values_.head(layout_->n_owned()); }
  auto owned() const { return values_.head(layout_->n_owned()); }
  /// Owners' values into the ghosts (after the owned entries changed).
  void update_ghosts() { layout_->forward(values_); }
  /// Ghost contributions added into their owners (after local assembly).
  void add_ghosts_to_owners() { layout_->reverse_add(values_); }

 private:
  std::shared_ptr<const Layout> layout_;
  Eigen::VectorXd values_;
};

}  // namespace vpc::la

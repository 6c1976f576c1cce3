#pragma once
// Data given as formulas (muParser): loads f0, f2, the gap g, the initial damage
// β0, boundary-part predicates and damage sources φ. Variables: x, y, z, t and,
// for φ, the point state: vm (|σ|_VM), tr_sigma, tr_eps, eps_eq (equivalent
// strain √(2/3 dev ε : dev ε)) and beta. Constants: pi, e.
#include "core/sym_tensor.hpp"

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace mu {
class Parser;
}

namespace vpc {

class Expression {
 public:
  /// The variables an expression may use.
  enum class Kind { Space, SpaceTime, PointState };

  /// Compiles `text`; throws vpc::Error naming `where` (e.g. "case.toml:12:7: loads.f0[1]"),
  /// the position in the formula and what is wrong (unknown variable, syntax).
  Expression(const std::string& text, Kind kind, const std::string& where);
  ~Expression();
  Expression(const Expression&) = delete;
  Expression& operator=(const Expression&) = delete;

  double operator()(const Point& x, double t = 0) const;
  /// For φ: the point state at an element (x = centroid).
  double operator()(const Point& x, double t, const SymTensor& sigma, const SymTensor& eps, double beta) const;

  const std::string& text() const { return text_; }
  /// Whether the formula uses x, y or z (a load that does not is uniform in space).
  bool uses_position() const { return uses_position_; }
  /// Whether the formula uses t (a gap that does not is evaluated once).
  bool uses_time() const { return uses_time_; }
  static std::vector<std::string> variables(Kind kind);

  /// Throws vpc::Error if an evaluation since construction gave a value that is not a
  /// finite number (NaN, ±inf), naming the formula's key (`where`), the value, the time
  /// and the point of the earliest such evaluation (the least t, then x). The scheme
  /// calls it through check_formulas (problem/problem.hpp) after each step's data.
  void check_finite() const;

 private:
  struct Vars {
    double x = 0, y = 0, z = 0, t = 0, vm = 0, tr_sigma = 0, tr_eps = 0, eps_eq = 0, beta = 1;
  };
  /// One parser per OpenMP thread (muParser evaluates through the variables'
  /// addresses, so a parser is not re-entrant): evaluation is thread-safe
  /// across the threads of OpenMP loops.
  struct Slot {
    std::unique_ptr<mu::Parser> parser;
    std::unique_ptr<Vars> vars;  // stable address for the parser
  };
  Slot& slot() const;
  double eval(Slot& s) const;
  void note_not_finite(const Vars& at, double value) const;
  std::string text_, where_;
  std::vector<Slot> slots_;
  bool uses_position_ = true, uses_time_ = true;
  Kind kind_;
  /// The earliest evaluation that was not finite (evaluations run in OpenMP loops,
  /// which exceptions must not leave: it is noted here and reported by check_finite).
  mutable std::mutex not_finite_mutex_;
  mutable std::optional<std::pair<Vars, double>> not_finite_;
};

}  // namespace vpc

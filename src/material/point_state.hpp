#pragma once
#include "core/sym_tensor.hpp"

namespace vpc {

/// What a law sees at one element: σ, ε(u) and β (β at the element centroid,
/// the mean of its nodal values: SPEC §2 step 1).
struct PointState {
  SymTensor sigma;
  SymTensor eps;
  double beta = 1;
  int dim = 3;  // the tensors' dimension: d (they live in S_d), but 3 in plane strain (σ33 ≠ 0)
  Point x{};    // where (the element centroid) and when (t_{n−1}): for laws given as formulas
  double t = 0;
};

}  // namespace vpc

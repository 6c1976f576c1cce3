#pragma once
// The [adapt] keys (docs/cases.md): when and where the mesh of a run is refined and coarsened
// (issue 51). Read by io/case_adapt.cpp, acted on by adapt/mesh_adaptivity.hpp.
#include <string>

namespace vpc {

struct AdaptSpec {
  /// Adapt after every this many accepted steps (the first at step `every`).
  int every = 1;
  /// Per adaptation, up to this many times: the step just taken is redone on the mesh adapted from
  /// its own solution (from the state before it, carried over). 0: the adapted mesh serves the next step.
  int resolve = 0;
  /// Dörfler's bulk fraction θ: for each part of the indicator (stress, contact, damage), the fewest cells
  /// that carry θ of its Σ η_K² are refined (the union of the three sets).
  double refine_fraction = 0.5;
  /// The cells that together carry at most this share of Σ η_K² (the smallest η_K first) may be
  /// coarsened, where coarsening changes z, σ and β by less than coarsen_tolerance.
  double coarsen_fraction = 0.05;
  /// The largest relative L2 change coarsening may make in each of z and σ (against ‖σ‖) and β
  /// (against |Ω|^½), summed over an adaptation.
  double coarsen_tolerance = 1e-3;
  /// The deepest refinement level (bisections below a coarse cell).
  int max_level = 10;
  /// Cells whose longest edge is at most this are not marked (length; 0: no limit).
  double min_size = 0;
  /// The most displacement unknowns (d × nodes) a refinement may make; marking is truncated in
  /// the indicator's order to stay within it (warned once).
  long long max_unknowns = 2'000'000;
  /// Weights of the indicator's three parts, each normalized to Σ_K η_K² = 1 (adapt/indicator.hpp), in the
  /// combined indicator (coarsening's candidates, the order a truncated marking keeps, VTU `indicator`);
  /// a part of weight 0 marks no cell for refinement.
  double stress_weight = 1, contact_weight = 1, damage_weight = 1;
  /// > 0: an adaptation that is due takes place only while the relative stress estimate
  /// (CellIndicators::stress_relative) is above this.
  double tolerance = 0;
  /// Where the keys are ("case.toml:31:1"), for messages about the section.
  std::string where;
};

}  // namespace vpc

// [adapt]: mesh adaptivity during the run (issue 51; adapt/adapt_spec.hpp, docs/cases.md).
#include "adapt/mesh_adaptivity.hpp"
#include "io/case_readers.hpp"

#include "core/error.hpp"

namespace vpc::case_file {

namespace {

/// A number in [lo, hi] (an open end where `open_lo` / `open_hi`).
double in_range(Section& a, const std::string& k, double fallback, double lo, double hi, bool open_lo, bool open_hi) {
  const double v = a.number(k, fallback);
  const bool ok = (open_lo ? v > lo : v >= lo) && (open_hi ? v < hi : v <= hi);
  if (!ok)
    fail("{}: expected a number in {}{}, {}{}, got {}", a.where(k), open_lo ? "(" : "[", lo, hi, open_hi ? ")" : "]", v);
  return v;
}

int integer_at_least(Section& a, const std::string& k, int fallback, int lo, int hi) {
  const int v = a.integer(k, fallback);
  if (v < lo || v > hi) fail("{}: expected an integer in [{}, {}], got {}", a.where(k), lo, hi, v);
  return v;
}

}  // namespace

std::optional<AdaptSpec> read_adapt(Section a, const Problem& p) {
  if (!a.exists()) return std::nullopt;
  AdaptSpec s;
  s.where = a.where_section() + ": [adapt]";
  s.every = integer_at_least(a, "every", s.every, 1, 1 << 30);
  s.resolve = integer_at_least(a, "resolve", s.resolve, 0, 20);
  s.refine_fraction = in_range(a, "refine_fraction", s.refine_fraction, 0, 1, true, false);
  s.coarsen_fraction = in_range(a, "coarsen_fraction", s.coarsen_fraction, 0, 1, false, true);
  s.coarsen_tolerance = in_range(a, "coarsen_tolerance", s.coarsen_tolerance, 0, 1, false, false);
  s.max_level = integer_at_least(a, "max_level", s.max_level, 0, 60);
  s.min_size = in_range(a, "min_size", s.min_size, 0, INFINITY, false, true);
  s.max_unknowns = integer_at_least(a, "max_unknowns", static_cast<int>(s.max_unknowns), 1, 1 << 30);
  s.stress_weight = in_range(a, "stress_weight", s.stress_weight, 0, INFINITY, false, true);
  s.contact_weight = in_range(a, "contact_weight", s.contact_weight, 0, INFINITY, false, true);
  s.damage_weight = in_range(a, "damage_weight", s.damage_weight, 0, INFINITY, false, true);
  if (s.stress_weight + s.contact_weight + s.damage_weight == 0)
    fail("{}: stress_weight, contact_weight and damage_weight are all 0: the indicator would mark nothing (give one "
         "a weight > 0, or remove [adapt])",
         s.where);
  s.tolerance = in_range(a, "tolerance", s.tolerance, 0, INFINITY, false, true);
  a.finish();
  check_adaptable(p, s);
  return s;
}

}  // namespace vpc::case_file

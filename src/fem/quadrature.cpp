#include "fem/quadrature.hpp"

#include <cassert>
#include <cmath>

namespace vpc {

const std::vector<QuadraturePoint>& simplex_rule(int d) {
  static const std::vector<QuadraturePoint> rules[4] = {
      {{{1, 0, 0, 0}, 1.0}},
      [] {
        const double a = 0.5 - 0.5 / std::sqrt(3.0), b = 1 - a;  // 2-point Gauss
        return std::vector<QuadraturePoint>{{{a, b, 0, 0}, 0.5}, {{b, a, 0, 0}, 0.5}};
      }(),
      std::vector<QuadraturePoint>{{{2. / 3, 1. / 6, 1. / 6, 0}, 1. / 3},
                                   {{1. / 6, 2. / 3, 1. / 6, 0}, 1. / 3},
                                   {{1. / 6, 1. / 6, 2. / 3, 0}, 1. / 3}},
      [] {
        const double a = 0.5854101966249685, b = 0.1381966011250105;
        return std::vector<QuadraturePoint>{{{a, b, b, b}, 0.25},
                                            {{b, a, b, b}, 0.25},
                                            {{b, b, a, b}, 0.25},
                                            {{b, b, b, a}, 0.25}};
      }()};
  assert(d >= 0 && d <= 3);
  return rules[d];
}

}  // namespace vpc

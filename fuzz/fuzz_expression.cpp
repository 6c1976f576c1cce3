// Fuzz target: formulas, vpc::Expression (muParser), compiled and evaluated.
//
// Input: the first byte chooses the variables (byte % 3: x, y, z; x, y, z, t;
// the point state of φ), the rest is the formula. It is evaluated at a few
// points, including extreme values. A vpc::Error is a correct rejection;
// anything else escaping, a crash, a hang or a sanitizer report is a bug.
#include "core/error.hpp"
#include "core/expression.hpp"

#include <cstdint>
#include <limits>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return -1;
  using Kind = vpc::Expression::Kind;
  const Kind kinds[3] = {Kind::Space, Kind::SpaceTime, Kind::PointState};
  const Kind kind = kinds[data[0] % 3];
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const vpc::Expression e(text, kind, "fuzz.toml:1:1: formula");
    constexpr double big = std::numeric_limits<double>::max(), nan = std::numeric_limits<double>::quiet_NaN();
    const vpc::Point points[] = {{0, 0, 0}, {1, -2, 3}, {big, -big, nan}, {1e-310, -0.0, 1e300}};
    for (const auto& x : points) {
      if (kind == Kind::PointState) {
        const vpc::SymTensor sigma{{x[0], x[1], x[2], 1, -1, 0.5}}, eps{{1e-3, -x[0], 0, x[2], 0, 0}};
        (void)e(x, x[1], sigma, eps, 0.5);
      } else {
        (void)e(x, x[2]);
      }
    }
  } catch (const vpc::Error&) {
  }
  return 0;
}

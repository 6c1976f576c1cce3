#pragma once
// The test bar of the contact-law tests (moving gap, obstacles, normal compliance):
// [0, 1], clamped at x = 0, contact at x = 1, pushed towards +x by f0 = 1 (alone its tip
// would move by 1/2), elastic-viscoplastic with damage, 10 steps to T = 1. `contact`
// is the rest of the file: a [contact] section and/or [[obstacle]] sections.
#include <string>

namespace vpc::test {

inline std::string bar_text(const std::string& contact) {
  return R"(
[case]
name = "bar"
[mesh]
generator = "interval"
lower = [0.0]
upper = [1.0]
cells = [8]
[boundary]
clamped = ["left"]
contact = ["right"]
[elasticity]
E = 1.0
[viscoplasticity]
law = "maxwell-damage"
[loads]
f0 = ["1"]
[time]
T = 1.0
steps = 10
)" + contact;
}

}  // namespace vpc::test

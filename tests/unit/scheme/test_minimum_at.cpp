// min β and its node: one rule for both engines and every rank count (issue 12):
// among equal minima, the smallest node index. tests/mpi/cases/uniform-beta-2d.toml
// checks the same through summary.json on 1-3 ranks.
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace vpc {
namespace {

TEST(MinimumAt, TiesGoToTheSmallestIndex) {
  const std::vector<double> beta = {1, 0, 0.5, 0, 0};
  const MinimumAt m = minimum_at(beta);
  EXPECT_EQ(m.value, 0);
  EXPECT_EQ(m.index, 1);
}

TEST(MinimumAt, TiesGoToTheSmallestGivenIndexNotTheFirstPosition) {
  // A rank's owned nodes in its own order, with their numbers in the mesh as read.
  const std::vector<double> beta = {1, 1, 1, 1};
  const std::vector<int> node = {7, 3, 9, 5};
  const MinimumAt m = minimum_at(beta, node);
  EXPECT_EQ(m.value, 1);
  EXPECT_EQ(m.index, 3);
}

TEST(MinimumAt, CombiningCandidatesFollowsTheSameRule) {
  // The reduction over ranks: rank order must not matter.
  const MinimumAt a{0.25, 12}, b{0.25, 4}, c{0.5, 0};
  EXPECT_EQ(minimum_at(a, b).index, 4);
  EXPECT_EQ(minimum_at(b, a).index, 4);
  EXPECT_EQ(minimum_at(c, a).index, 12);
  EXPECT_EQ(minimum_at(MinimumAt{}, c).index, 0);  // an empty candidate (a rank without nodes)
}

TEST(MinimumAt, EmptyHasNoIndex) {
  EXPECT_EQ(minimum_at(std::vector<double>{}).index, -1);
}

TEST(MinimumAt, OverTheProcessesOnOneProcessIsTheLocalRule) {
  // global_minimum_at: the one function behind the step reports' and summary.json's min β.
  const la::Comm one;
  const std::vector<double> beta = {0.5, 0.25, 0.25, 1};
  const std::vector<int> node = {4, 9, 2, 0};
  const MinimumAt m = global_minimum_at(one, beta, node);
  EXPECT_EQ(m.value, 0.25);
  EXPECT_EQ(m.index, 2);
  EXPECT_EQ(global_minimum_at(one, std::vector<double>{}).index, -1);
}

}  // namespace
}  // namespace vpc

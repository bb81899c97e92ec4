// The bytes a distributed search sends (search::wire): exact, cut messages refused, and a
// fingerprint that tells problems apart.
#include "sinew/search/wire.h"

#include <cmath>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>

#include "physics/physics_test_util.h"
#include "sinew/search/session.h"

namespace sinew::search {
namespace {

Problem problemFor(const physics::test_util::Character& c, double window_s) {
  physics::SimulationSettings simulation;
  simulation.seconds = window_s;
  return Problem::create(c.plan, c.asset.skeleton, c.target, GenomeSettings{}, simulation).value();
}

bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST(SearchWire, PointsAndResultsTravelBitForBitAndCutMessagesAreRefused) {
  const std::vector<std::vector<double>> points = {{0.1, 1.0 / 3.0, 0.5}, {1e-300, 0.0, 1.0}};
  const wire::Bytes bytes = wire::packPoints(7, points);
  Result<wire::Points> back = wire::unpackPoints(bytes);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back.value().id, 7u);
  EXPECT_EQ(back.value().points, points);

  std::vector<Evaluation> results(2);
  results[0].terms.total = 2.1888716867069773;
  results[0].terms.tracking = 1.0 / 7.0;
  results[0].terms.fell = true;
  results[0].terms.fall_reason = "LowerLeg_L touched the ground (Latin-1: \xe9)";
  results[1].terms.total = std::numeric_limits<double>::infinity();
  results[1].terms.diverged = true;
  results[1].cancelled = true;
  const wire::Bytes packed = wire::packResults(9, results);
  Result<wire::Results> got = wire::unpackResults(packed);
  ASSERT_TRUE(got.ok()) << got.message();
  ASSERT_EQ(got.value().results.size(), 2u);
  const Evaluation& a = got.value().results[0];
  const Evaluation& b = got.value().results[1];
  EXPECT_EQ(got.value().id, 9u);
  EXPECT_TRUE(sameBits(a.terms.total, results[0].terms.total));
  EXPECT_TRUE(sameBits(a.terms.tracking, results[0].terms.tracking));
  EXPECT_TRUE(a.terms.fell);
  EXPECT_EQ(a.terms.fall_reason, results[0].terms.fall_reason);
  EXPECT_TRUE(std::isinf(b.terms.total));
  EXPECT_TRUE(b.terms.diverged);
  EXPECT_TRUE(b.cancelled);

  // Every cut of either message is refused, never read past its end.
  for (size_t n = 0; n < bytes.size(); ++n)
    EXPECT_FALSE(wire::unpackPoints(std::span(bytes).first(n)).ok()) << n;
  for (size_t n = 0; n < packed.size(); ++n)
    EXPECT_FALSE(wire::unpackResults(std::span(packed).first(n)).ok()) << n;
}

TEST(SearchWire, TheFingerprintTellsAnotherProblemApart) {
  const physics::test_util::Character biped = physics::test_util::loadCharacter("biped_walk.bvh");
  const physics::test_util::Character hopper = physics::test_util::loadCharacter("hopper_hop.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  ASSERT_FALSE(hopper.plan.links.empty());
  const std::uint64_t walk = wire::fingerprint(problemFor(biped, 2.0));
  EXPECT_EQ(walk, wire::fingerprint(problemFor(biped, 2.0)));   // built twice: the same
  EXPECT_NE(walk, wire::fingerprint(problemFor(biped, 3.0)));   // another window
  EXPECT_NE(walk, wire::fingerprint(problemFor(hopper, 2.0)));  // another rig
  Problem weighted = problemFor(biped, 2.0);
  weighted.weights.energy *= 2.0;
  EXPECT_NE(walk, wire::fingerprint(weighted));
}

}  // namespace
}  // namespace sinew::search

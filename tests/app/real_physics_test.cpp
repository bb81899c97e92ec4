// Real motion capture made physical, end to end through the command line: a Bandai walk (real
// capture from ../shared/data) evolved on a short budget walks a 10 s replay without falling.
// bench/real_physics_bench.sh measures every real clip on the full 5-minute budget.
#include <cmath>
#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/test_support.h"

namespace sinew {
namespace {

TEST(RealPhysicsTest, ABandaiWalkEvolvesIntoATenSecondWalk) {
#ifdef SINEW_SANITIZED
  GTEST_SKIP() << "a search's outcome is a Release measurement (the sanitizers slow it 20x)";
#endif
  SINEW_REQUIRE_SHARED_DATA();
  const std::string clip =
      test::quote(test::sharedData() / "bvh" / "bandai_dataset-1_walk_angry_001.bvh");
  const test::TempDir dir;
  const test::CommandResult evolved = test::runSinew("evolve --rig " + clip +
                                                     " --generations 12 --seed 1 --out " +
                                                     test::quote(dir / "evolved"));
  ASSERT_EQ(evolved.exit_code, 0) << evolved.err;
  const test::CommandResult replay =
      test::runSinew("simulate --rig " + clip + " --controller " +
                     test::quote(dir / "evolved" / "best.json") + " --seconds 10 --json " +
                     test::quote(dir / "replay.json"));
  ASSERT_EQ(replay.exit_code, 0) << replay.err;
  std::ifstream in(dir / "replay.json");
  const nlohmann::json r = nlohmann::json::parse(in);
  std::printf("Bandai angry walk after 12 generations: %s %.2f s, %.2f m (%.2f m/s), tracking %.2f deg\n",
              r["fell"].get<bool>() ? "fell after" : "walked", r["seconds"].get<double>(),
              r["distance_m"].get<double>(), r["speed_m_s"].get<double>(),
              r["track_err_rad_rms"].get<double>() * 180.0 / M_PI);
  EXPECT_FALSE(r["fell"].get<bool>()) << r.value("fall_reason", "");
  EXPECT_NEAR(r["seconds"].get<double>(), 10.0, 1e-6);
  EXPECT_GT(r["distance_m"].get<double>(), 10.0);  // the clip walks 1.8 m/s
}

}  // namespace
}  // namespace sinew

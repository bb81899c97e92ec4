#include "sinew/motion/units.h"

#include <gtest/gtest.h>

namespace sinew::motion {
namespace {

TEST(UnitsTest, NamesRoundTripAndUnknownNamesAreRefused) {
  for (LengthUnit unit : kAllLengthUnits) {
    EXPECT_EQ(unitFromName(unitName(unit)), unit);
  }
  EXPECT_FALSE(unitFromName("furlong"));
  EXPECT_FALSE(upAxisFromName("X"));
}

TEST(UnitsTest, ZUpCentimetresMapToYUpMetresAndBack) {
  const SourceFrame frame{LengthUnit::kCentimetres, UpAxis::kZ};
  const glm::dvec3 up_in_file(0.0, 0.0, 170.0);
  const glm::dvec3 engine = frame.pointToEngine(up_in_file);
  EXPECT_NEAR(engine.y, 1.7, 1e-12);
  EXPECT_NEAR(engine.x, 0.0, 1e-12);
  EXPECT_NEAR(engine.z, 0.0, 1e-12);
  const glm::dvec3 p(12.5, -3.0, 44.0);
  const glm::dvec3 back = frame.pointFromEngine(frame.pointToEngine(p));
  EXPECT_NEAR(glm::length(back - p), 0.0, 1e-12);
  // A rotation about the file's up axis becomes a rotation about the engine's Y.
  const glm::dquat about_z = glm::angleAxis(0.7, glm::dvec3(0.0, 0.0, 1.0));
  const glm::dquat mapped = frame.rotationToEngine(about_z);
  const glm::dvec3 axis = glm::axis(mapped);
  EXPECT_NEAR(std::abs(axis.y), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(glm::dvec3(glm::eulerAngles(frame.rotationFromEngine(mapped) *
                                                      glm::conjugate(about_z)))),
              0.0, 1e-12);
}

}  // namespace
}  // namespace sinew::motion

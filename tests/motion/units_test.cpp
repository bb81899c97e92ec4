#include "sinew/motion/units.h"

#include <gtest/gtest.h>

namespace sinew::motion {
namespace {

TEST(UnitsTest, NamesRoundTripAndUnknownNamesAreRefused) {
  for (LengthUnit unit : {LengthUnit::kMetres, LengthUnit::kCentimetres, LengthUnit::kMillimetres,
                          LengthUnit::kInches}) {
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

// A stick figure: feet at the bottom of the up axis, head on top, arms out.
std::vector<glm::dvec3> figure(bool z_up, double scale) {
  std::vector<glm::dvec3> points = {{0, 90, 0},  {10, 0, 5},  {-10, 0, 5},
                                    {0, 170, 0}, {80, 140, 0}, {-80, 140, 0}};
  for (glm::dvec3& p : points) {
    p *= scale;
    if (z_up) p = {p.x, -p.z, p.y};
  }
  return points;
}

TEST(UnitsTest, DetectsUpAxisAndUnitFromAPosedFigure) {
  const std::vector<bool> leaf = {false, true, true, true, true, true};
  FrameDetection y_cm = detectFrame(figure(false, 1.0), leaf, 0);
  EXPECT_EQ(y_cm.frame.up, UpAxis::kY);
  EXPECT_EQ(y_cm.frame.unit, LengthUnit::kCentimetres);
  EXPECT_NEAR(y_cm.height_in_file_units, 170.0, 1e-9);
  FrameDetection z_m = detectFrame(figure(true, 0.01), leaf, 0);
  EXPECT_EQ(z_m.frame.up, UpAxis::kZ);
  EXPECT_EQ(z_m.frame.unit, LengthUnit::kMetres);
  EXPECT_FALSE(z_m.reason.empty());
  FrameDetection mm = detectFrame(figure(false, 10.0), leaf, 0);
  EXPECT_EQ(mm.frame.unit, LengthUnit::kMillimetres);
}

}  // namespace
}  // namespace sinew::motion

#include "sinew/creature/random_creature.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <glm/gtc/quaternion.hpp>

namespace sinew::creature {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegree = kPi / 180.0;
// The ankle stands this share of the creature's size above the ground, so that the body plan's
// foot box (1.5 foot radii = 0.042 of the size below the ankle) ends at the toe tip's level.
constexpr double kAnkleShare = 0.05;

// Numbers from mt19937_64's raw output, which the standard fixes (its distributions are not the
// same in every library version).
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : engine_(seed) {}
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  int integer(int lo, int hi) {  // [lo, hi]
    return std::min(hi, lo + static_cast<int>(unit() * (hi - lo + 1)));
  }
  bool chance(double p) { return unit() < p; }

 private:
  std::mt19937_64 engine_;
};

// a(phase) = sum over n = 1, 2 of A_n (sin(n phase + phi_n) - sin(phi_n)): one or two sinusoids,
// zero at phase 0 so the clip starts in the rest pose. Radians.
struct Wave {
  double amplitude[2] = {0.0, 0.0};
  double phase[2] = {0.0, 0.0};

  double at(double stride_phase) const {
    double a = 0.0;
    for (int n = 0; n < 2; ++n)
      a += amplitude[n] * (std::sin((n + 1) * stride_phase + phase[n]) - std::sin(phase[n]));
    return a;
  }
};

// Euler angles about Z, X and Y, applied in that order (R = Rz Rx Ry, as BVH's ZXY channels).
struct JointMotion {
  Wave z, x, y;

  glm::dquat at(double stride_phase) const {
    return glm::angleAxis(z.at(stride_phase), glm::dvec3(0.0, 0.0, 1.0)) *
           glm::angleAxis(x.at(stride_phase), glm::dvec3(1.0, 0.0, 0.0)) *
           glm::angleAxis(y.at(stride_phase), glm::dvec3(0.0, 1.0, 0.0));
  }
};

// A wave with amplitude in [lo, hi] degrees at the stride frequency and, half the time, a second
// harmonic of up to 0.4 of that.
Wave drawWave(Draw& draw, double lo_deg, double hi_deg, double phase) {
  Wave w;
  w.amplitude[0] = draw.uniform(lo_deg, hi_deg) * kDegree;
  w.phase[0] = phase;
  if (draw.chance(0.5)) {
    w.amplitude[1] = draw.uniform(0.0, 0.4) * w.amplitude[0];
    w.phase[1] = draw.uniform(0.0, 2.0 * kPi);
  }
  return w;
}

// Where a joint is in its leg decides which kinds it may be: the joint at the torso is a ball,
// hinge or fixed; joints below it and the foot are hinges or fixed. Measured on seeds 1..200
// held in their first pose under the PD controller for 2 s: with ball joints anywhere (on light,
// thin bones with little inertia about their axis) 32 reached Bullet's joint-speed clamp; with
// ball joints only at the torso, 11.
enum class Place : std::uint8_t { kTop, kMiddle, kFoot };

JointKind drawKind(Draw& draw, Place place) {
  const double u = draw.unit();
  switch (place) {
    case Place::kTop:
      return u < 0.45 ? JointKind::kBall : u < 0.9 ? JointKind::kHinge : JointKind::kFixed;
    case Place::kMiddle:
      return u < 0.85 ? JointKind::kHinge : JointKind::kFixed;
    case Place::kFoot:
      return u < 0.7 ? JointKind::kHinge : JointKind::kFixed;
  }
  return JointKind::kFixed;
}

// `gain` scales the amplitude ranges (the feet move half as much).
JointMotion drawMotion(Draw& draw, JointKind kind, double phase, double gain) {
  JointMotion m;
  const double jitter = draw.uniform(-0.6, 0.6);
  switch (kind) {
    case JointKind::kBall:
      m.x = drawWave(draw, 5.0 * gain, 15.0 * gain, phase + jitter);
      m.z = drawWave(draw, 3.0 * gain, 10.0 * gain, draw.uniform(0.0, 2.0 * kPi));
      m.y = drawWave(draw, 0.0, 5.0 * gain, draw.uniform(0.0, 2.0 * kPi));
      break;
    case JointKind::kHinge:
      m.x = drawWave(draw, 8.0 * gain, 20.0 * gain, phase + jitter);
      break;
    case JointKind::kFixed:
      break;
  }
  return m;
}

// Everything random about one leg, drawn before any geometry is built.
struct LimbDraw {
  std::string name;
  glm::dvec3 attach{0.0};        // on the torso, from the root, metres
  std::vector<double> weights;   // (segments) relative bone lengths
  std::vector<double> splay;     // (segments) angle from straight down, radians
  std::vector<double> azimuth;   // (segments) direction of the lean, radians from +Z toward +X
  double toe_length = 0.1;       // metres
  double toe_yaw = 0.0;          // radians from +Z toward +X
  std::vector<JointKind> kinds;  // (segments + 1) the last is the foot's
  std::vector<JointMotion> motion;
};

LimbDraw drawLimb(Draw& draw, std::string name, const glm::dvec3& attach, double side, int segments,
                  double scale, double phase) {
  LimbDraw limb;
  limb.name = std::move(name);
  limb.attach = attach;
  const double outward = side > 0.0   ? 0.5 * kPi
                         : side < 0.0 ? -0.5 * kPi
                                      : draw.uniform(0.0, 2.0 * kPi);
  for (int s = 0; s < segments; ++s) {
    limb.weights.push_back(draw.uniform(0.6, 1.4));
    if (s == 0) {
      limb.splay.push_back(draw.uniform(10.0, 45.0) * kDegree);
      limb.azimuth.push_back(outward + draw.uniform(-0.6, 0.6));
    } else {
      limb.splay.push_back(draw.uniform(0.0, 30.0) * kDegree);
      limb.azimuth.push_back(draw.uniform(0.0, 2.0 * kPi));
    }
  }
  limb.toe_length = scale * draw.uniform(0.08, 0.15);
  limb.toe_yaw = draw.uniform(-0.5, 0.5);
  for (int s = 0; s <= segments; ++s) {
    const JointKind kind = drawKind(draw, s == segments ? Place::kFoot
                                          : s == 0      ? Place::kTop
                                                        : Place::kMiddle);
    limb.kinds.push_back(kind);
    limb.motion.push_back(drawMotion(draw, kind, phase, s == segments ? 0.5 : 1.0));
  }
  return limb;
}

// A copy on the other side of the body: attachment and leans mirrored in X, the same bones and
// joint kinds, its motion `shift` radians later.
LimbDraw mirrored(const LimbDraw& limb, std::string name, double shift) {
  LimbDraw m = limb;
  m.name = std::move(name);
  m.attach.x = -m.attach.x;
  for (double& a : m.azimuth) a = -a;
  m.toe_yaw = -m.toe_yaw;
  for (JointMotion& jm : m.motion) {
    // Mirroring in X flips rotations about Y and Z.
    for (Wave* w : {&jm.x, &jm.y, &jm.z})
      for (int n = 0; n < 2; ++n) w->phase[n] += (n + 1) * shift;
    for (Wave* w : {&jm.y, &jm.z})
      for (double& a : w->amplitude) a = -a;
  }
  return m;
}

// Joint names by bone, top to bottom. Hinges say "Knee" (the body plan's hinge rule); no name
// holds a word the body plan or the mass model reads as a trunk, hand, head or toe.
constexpr const char* kBoneNames[] = {"UpLeg", "Leg", "LowLeg"};
constexpr const char* kHingeNames[] = {"UpKnee", "Knee", "LowKnee"};

std::string jointName(const LimbDraw& limb, int segment) {
  const int index = std::min(segment, 2);
  return limb.name + (limb.kinds[static_cast<size_t>(segment)] == JointKind::kHinge
                          ? kHingeNames[index]
                          : kBoneNames[index]);
}

// The bone directions of a leg and the length scale that makes its vertical drop `drop`.
std::vector<glm::dvec3> limbBones(const LimbDraw& limb, double drop) {
  std::vector<glm::dvec3> directions;
  double vertical = 0.0;
  for (size_t s = 0; s < limb.weights.size(); ++s) {
    const double t = limb.splay[s], a = limb.azimuth[s];
    directions.emplace_back(std::sin(t) * std::sin(a), -std::cos(t), std::sin(t) * std::cos(a));
    vertical += limb.weights[s] * std::cos(t);
  }
  const double scale = drop / vertical;
  std::vector<glm::dvec3> bones;
  for (size_t s = 0; s < directions.size(); ++s)
    bones.push_back(directions[s] * (limb.weights[s] * scale));
  return bones;
}

// The skeleton for drawn limbs with the ankles `ankle` metres above the ground.
motion::Skeleton buildSkeleton(const std::vector<LimbDraw>& limbs, double torso_height,
                               double ankle, std::vector<Limb>* out_limbs) {
  motion::Skeleton skeleton;
  skeleton.addJoint("Torso", motion::kNoParent, glm::dvec3(0.0, torso_height, 0.0));
  if (out_limbs != nullptr) out_limbs->clear();
  for (const LimbDraw& draw : limbs) {
    Limb limb;
    limb.name = draw.name;
    limb.kinds = draw.kinds;
    const std::vector<glm::dvec3> bones = limbBones(draw, torso_height + draw.attach.y - ankle);
    int parent = 0;
    glm::dvec3 offset = draw.attach;
    for (size_t s = 0; s < bones.size(); ++s) {
      parent = skeleton.addJoint(jointName(draw, static_cast<int>(s)), parent, offset);
      limb.joints.push_back(parent);
      offset = bones[s];
    }
    limb.foot = skeleton.addJoint(draw.name + "Foot", parent, offset);
    limb.joints.push_back(limb.foot);
    skeleton.end_sites[static_cast<size_t>(limb.foot)] = glm::dvec3(
        std::sin(draw.toe_yaw) * draw.toe_length, -ankle, std::cos(draw.toe_yaw) * draw.toe_length);
    if (out_limbs != nullptr) out_limbs->push_back(std::move(limb));
  }
  return skeleton;
}

// Largest extent of the rest pose (joints and End Sites), metres: the body plan's size.
double restSize(const motion::Skeleton& skeleton) {
  const std::vector<glm::dmat4> world = motion::restWorldTransforms(skeleton);
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const glm::dvec3 p(world[static_cast<size_t>(j)][3]);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    if (const auto& e = skeleton.end_sites[static_cast<size_t>(j)]) {
      const glm::dvec3 q(world[static_cast<size_t>(j)] * glm::dvec4(*e, 1.0));
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
  }
  const glm::dvec3 extent = hi - lo;
  return std::max({extent.x, extent.y, extent.z});
}

}  // namespace

const char* jointKindName(JointKind kind) {
  switch (kind) {
    case JointKind::kBall:
      return "ball";
    case JointKind::kHinge:
      return "hinge";
    case JointKind::kFixed:
      return "fixed";
  }
  return "?";
}

Status CreatureSettings::validate() const {
  if (min_limbs < 1 || max_limbs > 8 || min_limbs > max_limbs)
    return Status::error(
        "min_limbs and max_limbs must satisfy 1 <= min_limbs <= max_limbs <= 8 "
        "(got " +
        std::to_string(min_limbs) + ".." + std::to_string(max_limbs) + ")");
  if (min_segments < 1 || max_segments > 3 || min_segments > max_segments)
    return Status::error(
        "min_segments and max_segments must satisfy 1 <= min_segments <= "
        "max_segments <= 3 (got " +
        std::to_string(min_segments) + ".." + std::to_string(max_segments) + ")");
  if (!(std::isfinite(frame_rate_hz) && frame_rate_hz > 0.0 && frame_rate_hz <= 1000.0))
    return Status::error("frame_rate_hz must be in (0, 1000]");
  if (strides < 1 || strides > 100) return Status::error("strides must be in 1..100");
  return Status();
}

Result<Creature> randomCreature(const CreatureSettings& settings) {
  if (Status s = settings.validate(); !s.ok())
    return Status::error("creature settings: " + s.message());
  Draw draw(settings.seed);

  // Every draw is its own statement: the order in which a call's arguments are evaluated is
  // unspecified, and two draws in one call would give other creatures with another compiler.

  // The body: a box-like torso (its shape comes from where the legs attach) of `scale` metres.
  const int limb_count = draw.integer(settings.min_limbs, settings.max_limbs);
  const double scale = draw.uniform(0.4, 1.4);
  glm::dvec3 half(0.0);
  half.x = scale * draw.uniform(0.06, 0.14);
  half.y = scale * draw.uniform(0.05, 0.1);
  half.z = scale * draw.uniform(0.1, 0.25);
  const double torso_height = half.y + scale * draw.uniform(0.4, 0.75);

  // Legs in left-right pairs, front to back, and an odd one on the midline at the back (or, half
  // the time, the front). A pair is mirrored (same bones, in step or half a stride apart) three
  // times out of four; otherwise its two legs are drawn independently.
  const int pairs = limb_count / 2;
  const bool middle = limb_count % 2 == 1;
  const int slots = pairs + (middle ? 1 : 0);
  const double flip = draw.chance(0.5) ? 1.0 : -1.0;
  const auto slotZ = [&](int slot) {
    const double z = slots == 1 ? 0.0 : 0.85 * (1.0 - 2.0 * slot / (slots - 1));
    return flip * half.z * z;
  };
  const auto segmentCount = [&] {
    return draw.integer(settings.min_segments, settings.max_segments);
  };
  // A point under the torso on one side (+1 left, -1 right, 0 the midline) at a slot's z.
  const auto attachment = [&](double side, int slot) {
    glm::dvec3 a(0.0);
    if (side != 0.0) a.x = side * half.x * draw.uniform(0.5, 1.0);
    a.y = -half.y * draw.uniform(0.3, 1.0);
    a.z = slotZ(slot);
    if (side != 0.0) a.z += half.z * draw.uniform(-0.1, 0.1);
    return a;
  };
  std::vector<LimbDraw> limbs;
  for (int p = 0; p < pairs; ++p) {
    const std::string number = std::to_string(p + 1);
    const glm::dvec3 attach = attachment(1.0, p);
    const double phase = draw.uniform(0.0, 2.0 * kPi);
    const int segments = segmentCount();
    LimbDraw left = drawLimb(draw, "LeftLimb" + number, attach, 1.0, segments, scale, phase);
    if (draw.chance(0.75)) {
      const double shift = draw.chance(0.5) ? kPi : 0.0;
      limbs.push_back(left);
      limbs.push_back(mirrored(left, "RightLimb" + number, shift));
    } else {
      const glm::dvec3 other = attachment(-1.0, p);
      const double other_phase = draw.uniform(0.0, 2.0 * kPi);
      const int other_segments = segmentCount();
      limbs.push_back(std::move(left));
      limbs.push_back(
          drawLimb(draw, "RightLimb" + number, other, -1.0, other_segments, scale, other_phase));
    }
  }
  if (middle) {
    const glm::dvec3 attach = attachment(0.0, pairs);
    const double phase = draw.uniform(0.0, 2.0 * kPi);
    const int segments = segmentCount();
    limbs.push_back(
        drawLimb(draw, "MidLimb" + std::to_string(pairs + 1), attach, 0.0, segments, scale, phase));
  }
  JointMotion torso_motion;
  torso_motion.x = drawWave(draw, 0.0, 4.0, draw.uniform(0.0, 2.0 * kPi));
  torso_motion.z = drawWave(draw, 0.0, 4.0, draw.uniform(0.0, 2.0 * kPi));
  torso_motion.y = drawWave(draw, 0.0, 3.0, draw.uniform(0.0, 2.0 * kPi));
  const double period_s = draw.uniform(0.6, 1.2);

  // Geometry: first with the ankles on the ground to measure the size, then with the ankles
  // raised by a share of it (raising them only shortens the legs, so the size does not grow).
  Creature creature;
  const double ankle = kAnkleShare * restSize(buildSkeleton(limbs, torso_height, 0.0, nullptr));
  creature.skeleton = buildSkeleton(limbs, torso_height, ankle, &creature.limbs);
  creature.torso_height_m = torso_height;
  const motion::Skeleton& skeleton = creature.skeleton;

  // The clip: every joint's waves; the torso's height keeps the lowest point on the ground.
  creature.frames_per_stride =
      std::max(4, static_cast<int>(std::lround(period_s * settings.frame_rate_hz)));
  creature.stride_s = creature.frames_per_stride / settings.frame_rate_hz;
  std::vector<const JointMotion*> motion_of(static_cast<size_t>(skeleton.jointCount()), nullptr);
  motion_of[0] = &torso_motion;
  for (size_t l = 0; l < limbs.size(); ++l)
    for (size_t k = 0; k < creature.limbs[l].joints.size(); ++k)
      motion_of[static_cast<size_t>(creature.limbs[l].joints[k])] = &limbs[l].motion[k];

  motion::Clip& clip = creature.clip;
  clip.name = "creature";
  clip.frame_time = 1.0 / settings.frame_rate_hz;
  clip.frame_count = settings.strides * creature.frames_per_stride + 1;
  clip.joint_count = skeleton.jointCount();
  const size_t n = static_cast<size_t>(skeleton.jointCount());
  clip.rotations.resize(n * static_cast<size_t>(clip.frame_count));
  clip.translations.resize(clip.rotations.size());
  std::vector<glm::dmat4> world(n);
  for (int f = 0; f < clip.frame_count; ++f) {
    // Whole strides repeat exactly: the phase comes from the frame within its stride.
    const double phase = 2.0 * kPi * (f % creature.frames_per_stride) / creature.frames_per_stride;
    const size_t base = static_cast<size_t>(f) * n;
    for (size_t j = 0; j < n; ++j) {
      clip.rotations[base + j] = glm::normalize(motion_of[j]->at(phase));
      clip.translations[base + j] = skeleton.offsets[j];
    }
    clip.translations[base] = glm::dvec3(0.0);
    motion::worldTransforms(skeleton, clip, f, world);
    double lowest = std::numeric_limits<double>::max();
    for (size_t j = 0; j < n; ++j) {
      lowest = std::min(lowest, world[j][3].y);
      if (const auto& e = skeleton.end_sites[j])
        lowest = std::min(lowest, (world[j] * glm::dvec4(*e, 1.0)).y);
    }
    clip.translations[base] = glm::dvec3(0.0, -lowest, 0.0);
  }
  if (Status s = clip.validate(skeleton); !s.ok())
    return Status::error("creature " + std::to_string(settings.seed) + ": " + s.message());
  return creature;
}

}  // namespace sinew::creature

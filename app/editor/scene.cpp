#include "editor/scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <span>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "editor/ghost.h"
#include "editor/skinning.h"

namespace sinew::editor {
namespace {

const glm::vec4 kCentreColor{0.80f, 0.74f, 0.66f, 1.0f};
const glm::vec4 kLeftColor{0.55f, 0.70f, 0.88f, 1.0f};
const glm::vec4 kRightColor{0.90f, 0.58f, 0.50f, 1.0f};
const glm::vec4 kSelectedColor{1.00f, 0.72f, 0.20f, 1.0f};
const glm::vec4 kModelColor{0.45f, 0.95f, 0.85f, 0.5f};
const glm::vec4 kModelSelectedColor{1.00f, 0.80f, 0.30f, 0.55f};
const glm::vec4 kBestColor{0.55f, 1.00f, 0.45f, 0.85f};        // the population's best run
const glm::vec4 kIndividualColor{0.72f, 0.64f, 1.00f, 0.55f};  // the others
const glm::vec4 kPickedColor{1.00f, 0.95f, 0.80f, 0.90f};      // the one clicked
const glm::vec4 kGhostColor{0.92f, 0.92f, 0.95f, 0.40f};       // the target over a run: on it
const glm::vec4 kGhostRedColor{1.00f, 0.12f, 0.08f, 0.60f};    // kGhostRedDeg or more off
const float kXrayOpacity = 0.6f;                               // the skeleton drawn over the mesh
const size_t kBoundsSamples = 4096;  // skinned vertices per mesh looked at for the bounds

bool containsNoCase(const std::string& text, const char* word) {
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower.find(word) != std::string::npos;
}

// Left limbs blue, right limbs red, the rest bone coloured: how animators read a skeleton.
glm::vec4 sideColor(const std::string& name) {
  if (containsNoCase(name, "left") || (name.size() > 1 && name[0] == 'l' && std::isupper(name[1])))
    return kLeftColor;
  if (containsNoCase(name, "right") || (name.size() > 1 && name[0] == 'r' && std::isupper(name[1])))
    return kRightColor;
  return kCentreColor;
}

// The rest pose's joints' largest extent, file units.
double restExtent(const motion::Skeleton& skeleton) {
  const std::vector<glm::dmat4> rest = motion::restWorldTransforms(skeleton);
  glm::dvec3 lo(1e30), hi(-1e30);
  for (const glm::dmat4& m : rest) {
    lo = glm::min(lo, glm::dvec3(m[3]));
    hi = glm::max(hi, glm::dvec3(m[3]));
  }
  return rest.empty() ? 0.0 : std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
}

// World transforms at a fractional frame: local rotations slerped, translations and scales
// blended, between the two frames around it. (Blending world matrices instead would shorten bones
// and shrink a skinned mesh between frames: by 2 mm on the Fox's legs.)
void worldBetweenFrames(const motion::Skeleton& skeleton, const motion::Clip& clip, double frame,
                        std::span<glm::dmat4> out) {
  const int f0 = static_cast<int>(std::floor(frame));
  const int f1 = std::min(f0 + 1, clip.frame_count - 1);
  const double w = frame - f0;
  const int joints = skeleton.jointCount();
  motion::Clip pose;
  pose.frame_time = clip.frame_time;
  pose.frame_count = 1;
  pose.joint_count = joints;
  pose.rotations.resize(static_cast<size_t>(joints));
  pose.translations.resize(static_cast<size_t>(joints));
  if (!clip.scales.empty()) pose.scales.resize(static_cast<size_t>(joints));
  for (int j = 0; j < joints; ++j) {
    pose.rotations[j] = glm::slerp(clip.rotation(f0, j), clip.rotation(f1, j), w);
    pose.translations[j] = glm::mix(clip.translation(f0, j), clip.translation(f1, j), w);
    if (!pose.scales.empty()) pose.scales[j] = glm::mix(clip.scale(f0, j), clip.scale(f1, j), w);
  }
  motion::worldTransforms(skeleton, pose, 0, out);
}

// The bind-pose meshes' extent along `direction` (unit), drawn metres.
float meshWidth(const motion::MotionAsset& asset, const glm::vec3& direction) {
  float lo = 1e30f, hi = -1e30f;
  for (const motion::SkinnedMesh& mesh : asset.meshes) {
    const size_t step = std::max<size_t>(1, mesh.positions.size() / kBoundsSamples);
    for (size_t v = 0; v < mesh.positions.size(); v += step) {
      const glm::vec3 p(mesh.mesh_to_world * glm::dvec4(glm::dvec3(mesh.positions[v]), 1.0));
      lo = std::min(lo, glm::dot(p, direction));
      hi = std::max(hi, glm::dot(p, direction));
    }
  }
  return hi > lo ? hi - lo : 0.0f;
}

// The joints above the pelvis (pelvisJoint): a root that only carries the hips, often left at
// the origin (Bandai's joint_Root) while the character walks away. They carry no body, so no bone
// is drawn from them: it would be a pole across the scene, and the camera would frame the origin.
std::vector<bool> massless(const motion::Skeleton& skeleton) {
  std::vector<bool> above(static_cast<size_t>(skeleton.jointCount()), false);
  if (skeleton.jointCount() == 0) return above;
  for (int j = skeleton.parents[motion::pelvisJoint(skeleton)]; j != motion::kNoParent;
       j = skeleton.parents[j]) {
    above[static_cast<size_t>(j)] = true;
  }
  return above;
}

// What every part of the scene draws the character at: its size.
struct SceneFigure {
  const motion::MotionAsset& asset;
  int joints = 0;
  float height = 0.1f;  // rest extent, metres
  float radius = 0.0f;  // bone capsule radius, display units
  int pelvis = 0;
};

// One drawn bone: its capsule (colour unset), the joint it ends at (its side and selection
// colour) and the joint whose rotation turns it (the ghost's deviation colour).
struct Bone {
  CapsuleInstance capsule;
  int joint = 0;
  int turned_by = 0;
};

std::vector<Bone> bonesOf(const motion::Skeleton& skeleton, std::span<const glm::dmat4> world,
                          const glm::vec3& offset, float radius, bool end_sites) {
  std::vector<Bone> bones;
  const std::vector<bool> above_pelvis = massless(skeleton);
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (above_pelvis[static_cast<size_t>(j)]) continue;
    const glm::vec3 p = glm::vec3(world[j][3]) + offset;
    const int parent = skeleton.parents[j];
    if (parent != motion::kNoParent && !above_pelvis[static_cast<size_t>(parent)]) {
      const glm::vec3 q = glm::vec3(world[parent][3]) + offset;
      // No thicker than half its length: a chain of many short bones (10,000 joints) would
      // otherwise stack dozens of full-size capsules on every pixel (the renderer's cost).
      const float length = glm::length(p - q);
      if (length > 1e-4f) bones.push_back({{q, std::min(radius, 0.5f * length), p}, j, parent});
    } else {
      bones.push_back({{p, radius * 1.3f, p}, j, j});  // the body's root: a ball
    }
    if (end_sites && skeleton.end_sites[j]) {
      const glm::vec3 e = glm::vec3(world[j] * glm::dvec4(*skeleton.end_sites[j], 1.0)) + offset;
      const float length = glm::length(e - p);
      if (length > 1e-4f) bones.push_back({{p, std::min(radius * 0.8f, 0.5f * length), e}, j, j});
    }
  }
  return bones;
}

void appendBones(const motion::Skeleton& skeleton, std::span<const glm::dmat4> world,
                 const glm::vec3& offset, float radius, bool end_sites, int selected,
                 const glm::vec4* model_color, std::vector<CapsuleInstance>& out) {
  for (Bone& bone : bonesOf(skeleton, world, offset, radius, end_sites)) {
    const int j = bone.joint;
    glm::vec4 color = model_color != nullptr ? *model_color : sideColor(skeleton.names[j]);
    if (j == selected) color = model_color != nullptr ? kModelSelectedColor : kSelectedColor;
    bone.capsule.color = color;
    out.push_back(bone.capsule);
  }
}

// Neutral grey at no deviation to red at kGhostRedDeg and beyond.
glm::vec4 ghostColor(double deviation_rad) {
  const float w =
      static_cast<float>(std::clamp(glm::degrees(deviation_rad) / kGhostRedDeg, 0.0, 1.0));
  return glm::mix(kGhostColor, kGhostRedColor, w);
}

// The ghost over its run: the target's pose, its pelvis over the run's on the ground (so it
// stays over the run however far either travelled), each bone tinted by the deviation of the
// joint that turns it.
void appendGhost(const SceneFigure& figure, const Ghost& ghost,
                 std::span<const glm::dmat4> run_world, const glm::vec3& offset,
                 std::vector<CapsuleInstance>& out) {
  motion::Clip pose;
  pose.frame_time = 1.0;
  pose.frame_count = 1;
  pose.joint_count = figure.joints;
  pose.rotations = ghost.rotations;
  pose.translations = ghost.translations;
  std::vector<glm::dmat4> world(static_cast<size_t>(figure.joints));
  motion::worldTransforms(figure.asset.skeleton, pose, 0, world);
  glm::vec3 align = glm::vec3(run_world[figure.pelvis][3]) - glm::vec3(world[figure.pelvis][3]);
  align.y = 0.0f;
  for (Bone& bone :
       bonesOf(figure.asset.skeleton, world, offset + align, figure.radius * 1.15f, false)) {
    bone.capsule.color = ghostColor(ghost.deviation_rad[static_cast<size_t>(bone.turned_by)]);
    out.push_back(bone.capsule);
  }
}

void growBounds(Scene& scene, const std::vector<CapsuleInstance>& capsules) {
  for (const CapsuleInstance& c : capsules) {
    for (const glm::vec3& p : {c.a, c.b}) {
      scene.bounds_min = glm::min(scene.bounds_min, p - c.radius);
      scene.bounds_max = glm::max(scene.bounds_max, p + c.radius);
    }
  }
}

// Horizontal unit vector to the side of a travel velocity (+X when it stands still).
glm::vec3 sideOfTravel(const glm::dvec3& v) {
  if (glm::length(glm::dvec2(v.x, v.z)) > 1e-3) {
    return glm::normalize(glm::vec3(static_cast<float>(v.z), 0.0f, static_cast<float>(-v.x)));
  }
  return glm::vec3(1.0f, 0.0f, 0.0f);
}

// The original at the playback time, between the two frames around it: skinned meshes, bones.
void addOriginal(Scene& scene, const EditorState& state, const SceneFigure& figure) {
  const motion::Clip& clip = *state.clip();
  const motion::Skeleton& skeleton = figure.asset.skeleton;
  const double frame = std::clamp(state.playback.time_s / clip.frame_time, 0.0,
                                  static_cast<double>(clip.frame_count - 1));
  std::vector<glm::dmat4> world0(static_cast<size_t>(figure.joints));
  worldBetweenFrames(skeleton, clip, frame, world0);
  // The meshes skin with the transforms the capsules are placed by, so both show one pose.
  const bool meshes = state.view.show_mesh && !figure.asset.meshes.empty();
  if (state.view.show_original && meshes) {
    scene.asset = &figure.asset;
    for (size_t m = 0; m < figure.asset.meshes.size(); ++m) {
      const motion::SkinnedMesh& mesh = figure.asset.meshes[m];
      if (mesh.inverse_bind.size() != static_cast<size_t>(figure.joints)) continue;
      SkinnedDraw draw;
      draw.mesh = static_cast<int>(m);
      draw.skinning.resize(static_cast<size_t>(figure.joints));
      skinningMatrices(mesh, world0, draw.skinning);
      scene.skinned.push_back(std::move(draw));
    }
  }
  scene.root = glm::vec3(world0[figure.pelvis][3]);
  if (!state.view.show_original) return;
  if (!meshes) {
    appendBones(skeleton, world0, glm::vec3(0.0f), figure.radius, state.view.show_end_sites,
                state.selected_joint, nullptr, scene.opaque);
  } else if (state.view.show_skeleton) {
    appendBones(skeleton, world0, glm::vec3(0.0f), figure.radius * 0.6f, state.view.show_end_sites,
                state.selected_joint, nullptr, scene.xray);
    for (CapsuleInstance& c : scene.xray) c.color.a = kXrayOpacity;
  }
}

// The model at the same time (its phase origin is the analysed window's start), over the
// original or beside it.
void addModel(Scene& scene, const EditorState& state, const SceneFigure& figure) {
  const spectral::TargetMotion& target = state.analysis->target;
  if (target.jointCount() != figure.joints) return;
  const motion::Skeleton& skeleton = figure.asset.skeleton;
  motion::Clip pose;
  pose.frame_time = state.clip()->frame_time;
  pose.frame_count = 1;
  pose.joint_count = figure.joints;
  pose.rotations.resize(static_cast<size_t>(figure.joints));
  pose.translations.resize(static_cast<size_t>(figure.joints));
  if (!target.base_scales.empty()) pose.scales = target.base_scales;
  target.pose(state.playback.time_s - state.analysis->spectrum.window.start_s, pose.rotations,
              pose.translations);
  std::vector<glm::dmat4> model_world(static_cast<size_t>(figure.joints));
  motion::worldTransforms(skeleton, pose, 0, model_world);
  // Beside: to the character's side, perpendicular to its travel on the ground.
  glm::vec3 offset(0.0f);
  if (state.view.model_beside) {
    const glm::vec3 side = sideOfTravel(state.analysis->spectrum.travel_velocity);
    // Clear of the mesh when the original is drawn as one (arms out, a tail): the model's
    // skeleton is about as wide, so a full mesh width and a tenth apart.
    float apart = 0.45f * figure.height;
    if (!scene.skinned.empty()) {
      apart = std::max(apart, 1.1f * meshWidth(figure.asset, side));
    }
    offset = side * apart;
  }
  appendBones(skeleton, model_world, offset, figure.radius, state.view.show_end_sites,
              state.selected_joint, &kModelColor, scene.translucent);
}

// The search's population, best first, in a grid on the other side (rows of eight, further rows
// behind): each run replayed at the playback time (its own 10 s loop), travel removed so they
// stay beside the clip. Returned apart: they stay out of the bounds, the camera keeps framing
// the clip. Each drawn individual gets a pick box.
std::vector<CapsuleInstance> populationBones(Scene& scene, const EditorState& state,
                                             const SceneFigure& figure,
                                             const std::optional<Ghost>& ghost) {
  std::vector<CapsuleInstance> population;
  const EvolutionState& evolution = state.evolution;
  const search::Snapshot& snap = *evolution.snapshot;
  const std::vector<int> order = rankedIndividuals(snap);
  const glm::vec3 side =
      sideOfTravel(state.analysis ? state.analysis->spectrum.travel_velocity : glm::dvec3(0.0));
  const glm::vec3 forward(-side.z, 0.0f, side.x);
  constexpr size_t kColumns = 8;                        // the default 8 in one row; 16 in two
  constexpr float kLaneWidth = 0.6f, kRowDepth = 1.2f;  // of the character's height
  const size_t shown =
      std::min(order.size(), static_cast<size_t>(std::max(evolution.settings.shown, 1)));
  std::vector<glm::dmat4> run_world(static_cast<size_t>(figure.joints));
  for (size_t rank = 0; rank < shown; ++rank) {
    const size_t individual = static_cast<size_t>(order[rank]);
    if (individual >= snap.population_motions.size()) continue;
    const motion::Clip& run = snap.population_motions[individual];
    if (run.frame_count < 1 || run.joint_count != figure.joints) continue;
    const int f = replayedFrame(run, state.playback.time_s);
    motion::worldTransforms(figure.asset.skeleton, run, f, run_world);
    // Travel removed (the run stays in its lane beside the clip), height and falls kept.
    glm::vec3 offset = scene.root - glm::vec3(run_world[figure.pelvis][3]);
    offset.y = 0.0f;
    // Lanes: a body is about 0.3 of its height wide and, fallen, about its height long, so 0.6
    // of a height between lanes and 1.2 between rows keep runs (and falls) from crossing.
    offset -= side * (kLaneWidth * figure.height * static_cast<float>(rank % kColumns + 1));
    offset -= forward * (kRowDepth * figure.height * static_cast<float>(rank / kColumns));
    const size_t first = population.size();
    const bool picked = order[rank] == evolution.selected;
    appendBones(figure.asset.skeleton, run_world, offset, figure.radius * 0.9f, false, -1,
                picked      ? &kPickedColor
                : rank == 0 ? &kBestColor
                            : &kIndividualColor,
                population);
    PickBox box{order[rank], glm::vec3(1e30f), glm::vec3(-1e30f)};
    for (size_t i = first; i < population.size(); ++i) {
      const CapsuleInstance& c = population[i];
      box.lo = glm::min(box.lo, glm::min(c.a, c.b) - c.radius);
      box.hi = glm::max(box.hi, glm::max(c.a, c.b) + c.radius);
    }
    if (population.size() > first) scene.individuals.push_back(box);
    // After the box: a click picks the run, not the target drawn over it.
    if (ghost && ghost->individual == order[rank])
      appendGhost(figure, *ghost, run_world, offset, population);
  }
  return population;
}

// Bounds of what the camera frames (not the population, drawn after the model's shadows).
void finishScene(Scene& scene, const motion::MotionAsset& asset,
                 const std::vector<CapsuleInstance>& population) {
  scene.bounds_min = glm::vec3(1e30f);
  scene.bounds_max = glm::vec3(-1e30f);
  growBounds(scene, scene.opaque);
  growBounds(scene, scene.translucent);
  growBounds(scene, scene.xray);
  for (const SkinnedDraw& draw : scene.skinned) {
    growSkinnedBounds(asset.meshes[static_cast<size_t>(draw.mesh)], draw.skinning, kBoundsSamples,
                      scene.bounds_min, scene.bounds_max);
  }
  scene.translucent_casters = scene.translucent.size();
  scene.translucent.insert(scene.translucent.end(), population.begin(), population.end());
  scene.empty = scene.opaque.empty() && scene.translucent.empty() && scene.skinned.empty() &&
                scene.xray.empty();
  if (scene.empty) scene.bounds_min = scene.bounds_max = scene.root;
}

}  // namespace

Scene buildScene(const EditorState& state) {
  Scene scene;
  scene.shadows = state.view.shadows;
  if (state.clip() == nullptr) return scene;
  const motion::MotionAsset& asset = *state.asset;
  const int joints = asset.skeleton.jointCount();
  const float height = static_cast<float>(std::max(restExtent(asset.skeleton), 0.1));
  const SceneFigure figure{asset, joints, height, 0.022f * height,
                           joints > 0 ? motion::pelvisJoint(asset.skeleton) : 0};
  addOriginal(scene, state, figure);
  if (state.view.show_model && state.analysis) addModel(scene, state, figure);
  std::vector<CapsuleInstance> population;
  const EvolutionState& evolution = state.evolution;
  if (evolution.show_population && evolution.snapshot &&
      !evolution.snapshot->population_motions.empty()) {
    population = populationBones(scene, state, figure, currentGhost(state));
  }
  finishScene(scene, asset, population);
  return scene;
}

int capsuleDetail(size_t count, int coarsest) {
  int detail = std::clamp(coarsest, 0, kCapsuleDetails - 1);
  while (detail + 1 < kCapsuleDetails && count * kCapsuleTriangles[detail] > kCapsuleTriangleBudget)
    ++detail;
  return detail;
}

std::span<const CapsuleInstance> capsulesWithinBudget(std::span<const CapsuleInstance> capsules,
                                                      std::vector<CapsuleInstance>& scratch) {
  const size_t most = kCapsuleTriangleBudget / kCapsuleTriangles[kCapsuleDetails - 1];
  if (capsules.size() <= most) return capsules;
  scratch.assign(capsules.begin(), capsules.end());
  const auto size = [](const CapsuleInstance& c) {
    return glm::length(c.b - c.a) + 2.0f * c.radius;
  };
  std::nth_element(
      scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(most), scratch.end(),
      [&](const CapsuleInstance& x, const CapsuleInstance& y) { return size(x) > size(y); });
  scratch.resize(most);
  return scratch;
}

int pickIndividual(const Scene& scene, const glm::vec3& origin, const glm::vec3& direction) {
  int best = -1;
  float nearest = 1e30f;
  for (const PickBox& box : scene.individuals) {
    // Slabs: the ray's entry and exit distances through the box.
    float enter = 0.0f, leave = 1e30f;
    for (int axis = 0; axis < 3; ++axis) {
      if (std::abs(direction[axis]) < 1e-8f) {
        if (origin[axis] < box.lo[axis] || origin[axis] > box.hi[axis]) leave = -1.0f;
        continue;
      }
      float t0 = (box.lo[axis] - origin[axis]) / direction[axis];
      float t1 = (box.hi[axis] - origin[axis]) / direction[axis];
      if (t0 > t1) std::swap(t0, t1);
      enter = std::max(enter, t0);
      leave = std::min(leave, t1);
    }
    if (enter <= leave && enter < nearest) {
      nearest = enter;
      best = box.individual;
    }
  }
  return best;
}

}  // namespace sinew::editor

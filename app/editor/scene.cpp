#include "editor/scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <span>

#include <glm/gtc/matrix_transform.hpp>

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

// The character's size: the rest pose's extent, so capsules scale with any rig.
float characterHeight(const motion::Skeleton& skeleton) {
  const std::vector<glm::dmat4> rest = motion::restWorldTransforms(skeleton);
  glm::dvec3 lo(1e30), hi(-1e30);
  for (const glm::dmat4& m : rest) {
    lo = glm::min(lo, glm::dvec3(m[3]));
    hi = glm::max(hi, glm::dvec3(m[3]));
  }
  const double extent = rest.empty() ? 1.0 : std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  return static_cast<float>(std::max(extent, 0.1));
}

void appendBones(const motion::Skeleton& skeleton, std::span<const glm::dmat4> world,
                 const glm::vec3& offset, float radius, bool end_sites, int selected,
                 const glm::vec4* model_color, std::vector<CapsuleInstance>& out) {
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const glm::vec3 p = glm::vec3(world[j][3]) + offset;
    glm::vec4 color = model_color != nullptr ? *model_color : sideColor(skeleton.names[j]);
    if (j == selected) color = model_color != nullptr ? kModelSelectedColor : kSelectedColor;
    const int parent = skeleton.parents[j];
    if (parent != motion::kNoParent) {
      const glm::vec3 q = glm::vec3(world[parent][3]) + offset;
      if (glm::length(p - q) > 1e-4f) out.push_back({q, radius, p, 0.0f, color});
    } else {
      out.push_back({p, radius * 1.3f, p, 0.0f, color});  // the root: a ball
    }
    if (end_sites && skeleton.end_sites[j]) {
      const glm::vec3 e = glm::vec3(world[j] * glm::dvec4(*skeleton.end_sites[j], 1.0)) + offset;
      if (glm::length(e - p) > 1e-4f) out.push_back({p, radius * 0.8f, e, 0.0f, color});
    }
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

}  // namespace

Scene buildScene(const EditorState& state) {
  Scene scene;
  const motion::Clip* clip = state.clip();
  if (clip == nullptr) return scene;
  const motion::Skeleton& skeleton = state.asset->skeleton;
  const int joints = skeleton.jointCount();
  const float height = characterHeight(skeleton);
  const float radius = 0.022f * height;

  // The original, between the two frames around the playback time (positions blended).
  const double frame = std::clamp(state.playback.time_s / clip->frame_time, 0.0,
                                  static_cast<double>(clip->frame_count - 1));
  const int f0 = static_cast<int>(std::floor(frame));
  const int f1 = std::min(f0 + 1, clip->frame_count - 1);
  const double w = frame - f0;
  std::vector<glm::dmat4> world0(static_cast<size_t>(joints)), world1(static_cast<size_t>(joints));
  motion::worldTransforms(skeleton, *clip, f0, world0);
  motion::worldTransforms(skeleton, *clip, f1, world1);
  for (int j = 0; j < joints; ++j) {
    for (int c = 0; c < 4; ++c) world0[j][c] = world0[j][c] * (1.0 - w) + world1[j][c] * w;
  }
  scene.root = glm::vec3(world0[0][3]);
  if (state.view.show_original) {
    appendBones(skeleton, world0, glm::vec3(0.0f), radius, state.view.show_end_sites,
                state.selected_joint, nullptr, scene.opaque);
  }

  // The model at the same time (its phase origin is the analysed window's start).
  if (state.view.show_model && state.analysis) {
    const spectral::TargetMotion& target = state.analysis->target;
    if (target.jointCount() == joints) {
      motion::Clip pose;
      pose.frame_time = clip->frame_time;
      pose.frame_count = 1;
      pose.joint_count = joints;
      pose.rotations.resize(static_cast<size_t>(joints));
      pose.translations.resize(static_cast<size_t>(joints));
      if (!target.base_scales.empty()) pose.scales = target.base_scales;
      target.pose(state.playback.time_s - state.analysis->spectrum.window.start_s, pose.rotations,
                  pose.translations);
      std::vector<glm::dmat4> model_world(static_cast<size_t>(joints));
      motion::worldTransforms(skeleton, pose, 0, model_world);
      // Beside: to the character's side, perpendicular to its travel on the ground.
      glm::vec3 offset(0.0f);
      if (state.view.model_beside) {
        const glm::dvec3 v = state.analysis->spectrum.travel_velocity;
        glm::vec3 side(1.0f, 0.0f, 0.0f);
        if (glm::length(glm::dvec2(v.x, v.z)) > 1e-3) {
          side = glm::normalize(glm::vec3(static_cast<float>(v.z), 0.0f, static_cast<float>(-v.x)));
        }
        offset = side * (0.45f * height);
      }
      appendBones(skeleton, model_world, offset, radius, state.view.show_end_sites,
                  state.selected_joint, &kModelColor, scene.translucent);
    }
  }
  // The search's population, best first, in a grid on the other side (rows of eight, further rows
  // behind): each run replayed at the playback time (its own 10 s loop), travel removed so they
  // stay beside the clip. They stay out of the bounds: the camera keeps framing the clip.
  std::vector<CapsuleInstance> population;
  const EvolutionState& evolution = state.evolution;
  if (evolution.show_population && evolution.snapshot &&
      !evolution.snapshot->population_motions.empty()) {
    const search::Snapshot& snap = *evolution.snapshot;
    std::vector<size_t> order(snap.population_motions.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return snap.population_terms[a].total < snap.population_terms[b].total;
    });
    const glm::dvec3 v =
        state.analysis ? state.analysis->spectrum.travel_velocity : glm::dvec3(0.0);
    glm::vec3 side(1.0f, 0.0f, 0.0f);
    if (glm::length(glm::dvec2(v.x, v.z)) > 1e-3)
      side = glm::normalize(glm::vec3(static_cast<float>(v.z), 0.0f, static_cast<float>(-v.x)));
    const glm::vec3 forward(-side.z, 0.0f, side.x);
    constexpr size_t kColumns = 8;  // the default 8 in one row; 16 in two
    const size_t shown =
        std::min(order.size(), static_cast<size_t>(std::max(evolution.settings.shown, 1)));
    std::vector<glm::dmat4> run_world(static_cast<size_t>(joints));
    for (size_t rank = 0; rank < shown; ++rank) {
      const motion::Clip& run = snap.population_motions[order[rank]];
      if (run.frame_count < 1 || run.joint_count != joints) continue;
      const double duration = std::max(run.duration(), run.frame_time);
      const double t = std::fmod(state.playback.time_s, duration);
      const int f = std::clamp(static_cast<int>(t / run.frame_time), 0, run.frame_count - 1);
      motion::worldTransforms(skeleton, run, f, run_world);
      // Travel removed (the run stays beside the clip), height and falls kept.
      glm::vec3 offset = scene.root - glm::vec3(run_world[0][3]);
      offset.y = 0.0f;
      offset -= side * (0.5f * height * static_cast<float>(rank % kColumns + 1));
      offset -= forward * (0.7f * height * static_cast<float>(rank / kColumns));
      const size_t first = population.size();
      const bool picked = static_cast<int>(order[rank]) == evolution.selected;
      appendBones(skeleton, run_world, offset, radius * 0.9f, false, -1,
                  picked      ? &kPickedColor
                  : rank == 0 ? &kBestColor
                              : &kIndividualColor,
                  population);
      PickBox box{static_cast<int>(order[rank]), glm::vec3(1e30f), glm::vec3(-1e30f)};
      for (size_t i = first; i < population.size(); ++i) {
        const CapsuleInstance& c = population[i];
        box.lo = glm::min(box.lo, glm::min(c.a, c.b) - c.radius);
        box.hi = glm::max(box.hi, glm::max(c.a, c.b) + c.radius);
      }
      if (population.size() > first) scene.individuals.push_back(box);
    }
  }

  scene.bounds_min = glm::vec3(1e30f);
  scene.bounds_max = glm::vec3(-1e30f);
  growBounds(scene, scene.opaque);
  growBounds(scene, scene.translucent);
  scene.translucent.insert(scene.translucent.end(), population.begin(), population.end());
  scene.empty = scene.opaque.empty() && scene.translucent.empty();
  if (scene.empty) scene.bounds_min = scene.bounds_max = scene.root;
  return scene;
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

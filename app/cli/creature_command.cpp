// sinew creature --random --seed N -o FILE: a random articulated creature (torso and legs) with a
// default periodic clip, as BVH or glTF; always a valid physics body plan.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "sinew/creature/random_creature.h"
#include "sinew/physics/body_plan.h"

namespace sinew::app {
namespace {

struct CreatureArgs {
  bool random = false;
  std::string seed;
  std::string output;
  std::string limbs;
};

// A whole number filling all of `text`.
template <class T>
bool parseWhole(std::string_view text, T& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && !text.empty();
}

// "N" or "MIN..MAX".
Result<std::pair<int, int>> parseLimbs(const std::string& text) {
  const Status bad = Status::error(
      "--limbs: expected N or MIN..MAX with 1 <= MIN <= MAX <= 8, got '" + text + "'");
  const size_t dots = text.find("..");
  int lo = 0, hi = 0;
  if (dots == std::string::npos) {
    if (!parseWhole(std::string_view(text), lo)) return bad;
    hi = lo;
  } else if (!parseWhole(std::string_view(text).substr(0, dots), lo) ||
             !parseWhole(std::string_view(text).substr(dots + 2), hi)) {
    return bad;
  }
  if (lo < 1 || hi > 8 || lo > hi) return bad;
  return std::pair<int, int>(lo, hi);
}

int runCreature(const CreatureArgs& args) {
  if (!args.random)
    return fail("creature: --random is required (random creatures are the only kind so far)");
  if (args.seed.empty()) return fail("creature: --seed N is required (a whole number >= 0)");
  if (args.output.empty()) return fail("creature: -o FILE is required (.bvh, .glb or .gltf)");
  creature::CreatureSettings settings;
  if (!parseWhole(std::string_view(args.seed), settings.seed))
    return fail("--seed: expected a whole number >= 0, got '" + args.seed + "'");
  if (!args.limbs.empty()) {
    Result<std::pair<int, int>> limbs = parseLimbs(args.limbs);
    if (!limbs.ok()) return fail(limbs.message());
    settings.min_limbs = limbs.value().first;
    settings.max_limbs = limbs.value().second;
  }
  std::string extension = std::filesystem::path(args.output).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".bvh" && extension != ".glb" && extension != ".gltf")
    return fail(args.output + ": unknown file type '" + extension +
                "', expected .bvh, .glb or .gltf");

  Result<creature::Creature> made = creature::randomCreature(settings);
  if (!made.ok()) return fail(made.message());
  const creature::Creature& c = made.value();
  // The promise of the command: the creature is a valid body plan. Checked before writing.
  Result<physics::BodyPlan> plan = physics::buildBodyPlan(c.skeleton, &c.clip);
  if (!plan.ok()) return fail("creature seed " + args.seed + ": body plan: " + plan.message());

  motion::MotionAsset asset;
  asset.path = args.output;
  asset.skeleton = c.skeleton;
  asset.clips = {c.clip};
  if (Status status = motion::exportMotion(args.output, asset, c.clip); !status.ok())
    return fail(status.message());

  std::string bones;
  for (const creature::Limb& limb : c.limbs) {
    if (!bones.empty()) bones += ' ';
    bones += std::to_string(limb.joints.size() - 1);
  }
  char line[256];
  std::snprintf(line, sizeof(line),
                ": %zu %s (bones %s), %d joints, %d frames at %g fps (%d strides of %.3f s); "
                "body plan %zu links, %d DOF, %.2f kg\n",
                c.limbs.size(), c.limbs.size() == 1 ? "leg" : "legs", bones.c_str(),
                c.skeleton.jointCount(), c.clip.frame_count, c.clip.fps(),
                (c.clip.frame_count - 1) / c.frames_per_stride, c.stride_s,
                plan.value().links.size(), plan.value().dofCount(), plan.value().total_mass_kg);
  std::cout << "wrote " << args.output << ": creature seed " << args.seed << line;
  return 0;
}

}  // namespace

void addCreatureCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<CreatureArgs>();
  CLI::App* command =
      app.add_subcommand("creature",
                         "Generate a random articulated creature (a torso and legs) with a looping "
                         "clip; it always builds a valid physics body plan");
  command->add_flag("--random", args->random, "A random creature (the only kind so far)");
  command->add_option("--seed", args->seed,
                      "Random seed, a whole number: the same seed gives "
                      "the same file");
  command->add_option("-o,--output", args->output, "The file to write (.bvh, .glb or .gltf)");
  command->add_option("--limbs", args->limbs, "Number of legs, N or MIN..MAX (1..8; default 2..6)");
  command->callback([args, &exit_code]() { exit_code = runCreature(*args); });
}

}  // namespace sinew::app

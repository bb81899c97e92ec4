#include "editor/history.h"

#include <cstdio>
#include <filesystem>
#include <map>

namespace sinew::editor {
namespace {

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::string onOff(bool value) {
  return value ? "on" : "off";
}

}  // namespace

void History::reset(app::Project current) {
  undo_.clear();
  redo_.clear();
  current_ = std::move(current);
}

bool History::record(const app::Project& current) {
  if (current == current_) return false;
  undo_.push_back(std::move(current_));
  if (undo_.size() > limit_) undo_.erase(undo_.begin());
  redo_.clear();
  current_ = current;
  return true;
}

std::optional<History::Step> History::undo() {
  if (undo_.empty()) return std::nullopt;
  Step step{undo_.back(), describeChange(undo_.back(), current_)};
  undo_.pop_back();
  redo_.push_back(std::move(current_));
  current_ = step.value;
  return step;
}

std::optional<History::Step> History::redo() {
  if (redo_.empty()) return std::nullopt;
  Step step{redo_.back(), describeChange(current_, redo_.back())};
  redo_.pop_back();
  undo_.push_back(std::move(current_));
  current_ = step.value;
  return step;
}

std::string History::undoLabel() const {
  return undo_.empty() ? "" : describeChange(undo_.back(), current_);
}

std::string History::redoLabel() const {
  return redo_.empty() ? "" : describeChange(current_, redo_.back());
}

std::string describeChange(const app::Project& before, const app::Project& after) {
  std::vector<std::string> changes;
  if (before.rig != after.rig || before.clip != after.clip) {
    const std::string& file = after.clip.empty() ? after.rig : after.clip;
    changes.push_back("opened " + std::filesystem::path(file).filename().string());
  } else if (before.animation != after.animation) {
    changes.push_back("animation " + after.animation);
  } else {
    // K per joint: a joint not listed has the project's K ("harmonics").
    std::map<std::string, std::pair<int, int>> joints;  // name -> (before, after)
    for (const auto& [joint, k] : before.joint_k) joints[joint] = {k, after.harmonics};
    for (const auto& [joint, k] : after.joint_k) {
      if (!joints.count(joint)) joints[joint].first = before.harmonics;
      joints[joint].second = k;
    }
    if (before.harmonics == after.harmonics) {
      for (const auto& [joint, k] : joints) {
        if (k.first != k.second) {
          changes.push_back("K of " + joint + " " + std::to_string(k.first) + " -> " +
                            std::to_string(k.second));
        }
      }
    }
  }
  if (before.harmonics != after.harmonics)
    changes.push_back("K of most joints " + std::to_string(before.harmonics) + " -> " +
                      std::to_string(after.harmonics));
  if (before.edits.band_gains != after.edits.band_gains) changes.push_back("band gains");
  if (before.edits.styles != after.edits.styles) {
    if (before.edits.styles.size() != after.edits.styles.size()) {
      changes.push_back(after.edits.styles.size() > before.edits.styles.size() ? "style added"
                                                                               : "style removed");
    } else {
      for (size_t i = 0; i < after.edits.styles.size(); ++i) {
        if (before.edits.styles[i].weight != after.edits.styles[i].weight)
          changes.push_back("style " + after.edits.styles[i].label + " weight " +
                            number(after.edits.styles[i].weight));
      }
    }
  }
  if (before.edits.secondary != after.edits.secondary) changes.push_back("secondary motion");
  const app::PhysicsSettings& pa = before.physics;
  const app::PhysicsSettings& pb = after.physics;
  if (app::terrainText(pa.terrain) != app::terrainText(pb.terrain))
    changes.push_back("terrain " + app::terrainText(pb.terrain));
  if (pa.window_s != pb.window_s) changes.push_back("window " + number(pb.window_s) + " s");
  {
    app::PhysicsSettings same = pa;
    same.pushes = pb.pushes;
    if (!(same == pa)) changes.push_back("pushes");
  }
  if (!(pa.body == pb.body)) changes.push_back("body overrides");
  const app::SearchSettings& a = before.search;
  const app::SearchSettings& b = after.search;
  if (a.minutes != b.minutes) changes.push_back("budget " + number(b.minutes) + " min");
  if (a.population != b.population) changes.push_back("population " + std::to_string(b.population));
  if (a.no_prior != b.no_prior) changes.push_back("no prior " + onOff(b.no_prior));
  if (a.optimizer != b.optimizer)
    changes.push_back(std::string("optimizer ") + search::optimizerName(b.optimizer));
  if (a.seed != b.seed) changes.push_back("seed " + std::to_string(b.seed));
  if (a.trials != b.trials) changes.push_back("trials " + std::to_string(b.trials));
  if (a.restart_after != b.restart_after)
    changes.push_back("restart after " + std::to_string(b.restart_after) + " generations");
  if (a.start_generations != b.start_generations)
    changes.push_back("try starts " + std::to_string(b.start_generations) + " generations");
  if (a.trial_push_m_s != b.trial_push_m_s)
    changes.push_back("trial push " + number(b.trial_push_m_s) + " m/s");
  if (a.robust_push_m_s != b.robust_push_m_s)
    changes.push_back("pushes in every run " + number(b.robust_push_m_s) + " m/s");
  search::FitnessWeights wa = a.weights, wb = b.weights;
  for (int term = 0; term < search::kFitnessTermCount; ++term) {
    if (search::fitnessWeight(wa, term) != search::fitnessWeight(wb, term)) {
      changes.push_back(std::string("weight ") + search::fitnessTermName(term) + " " +
                        number(search::fitnessWeight(wa, term)) + " -> " +
                        number(search::fitnessWeight(wb, term)));
    }
  }
  const app::ViewSettings& va = before.view;
  const app::ViewSettings& vb = after.view;
  if (va.speed != vb.speed) changes.push_back("speed " + number(vb.speed) + "x");
  if (va.loop != vb.loop) changes.push_back("loop " + onOff(vb.loop));
  if (va.show_original != vb.show_original)
    changes.push_back("original " + onOff(vb.show_original));
  if (va.show_model != vb.show_model) changes.push_back("model " + onOff(vb.show_model));
  if (va.model_beside != vb.model_beside)
    changes.push_back(vb.model_beside ? "model beside" : "model overlaid");
  if (va.follow != vb.follow) changes.push_back("follow " + onOff(vb.follow));
  if (va.show_grid != vb.show_grid) changes.push_back("grid " + onOff(vb.show_grid));
  if (va.show_end_sites != vb.show_end_sites)
    changes.push_back("end sites " + onOff(vb.show_end_sites));
  if (va.show_population != vb.show_population)
    changes.push_back("population " + onOff(vb.show_population));
  if (va.show_ghost != vb.show_ghost) changes.push_back("ghost " + onOff(vb.show_ghost));
  if (before.target != after.target) changes.push_back("target " + after.target);
  if (changes.empty()) return "";
  if (changes.size() == 1) return changes[0];
  if (changes.size() == 2) return changes[0] + ", " + changes[1];
  return changes[0] + " and " + std::to_string(changes.size() - 1) + " more";
}

}  // namespace sinew::editor

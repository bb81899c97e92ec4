// Evolve: runs the search on the loaded rig from the model being edited and shows it live: the
// budget and window, start/pause/resume/stop, the generation, the best individual's terms, the
// best cost per generation (the Export panel writes the best). The
// viewport replays the population's runs beside the clip while it is shown.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <imgui.h>

#include "editor/ghost.h"
#include "editor/panels/panels.h"
#include "sinew/physics/joint_figures.h"
#include "sinew/pipeline/pipeline.h"

namespace sinew::editor {
namespace {

// Per generation, the lowest total cost and the lowest value of each weighted term, one line each
// on a shared scale (log10: the terms span decades), with a legend: which part of the fitness
// the search is buying down.
void plotHistory(const search::Snapshot& snap) {
  if (snap.history.empty()) return;
  constexpr int kLines = search::kFitnessTermCount + 1;
  const ImU32 colors[kLines] = {IM_COL32(240, 240, 240, 255), IM_COL32(235, 90, 80, 255),
                                IM_COL32(110, 200, 95, 255),  IM_COL32(85, 145, 240, 255),
                                IM_COL32(230, 180, 60, 255),  IM_COL32(190, 120, 230, 255),
                                IM_COL32(90, 210, 200, 255),  IM_COL32(160, 160, 160, 255)};
  auto value = [&](const search::GenerationRecord& r, int line) {
    const double v = line == 0 ? r.total.best : r.terms[static_cast<size_t>(line - 1)].best;
    return std::log10(std::max(v, 1e-3));
  };
  double lo = 1e30, hi = -1e30;
  for (const search::GenerationRecord& r : snap.history) {
    for (int line = 0; line < kLines; ++line) {
      lo = std::min(lo, value(r, line));
      hi = std::max(hi, value(r, line));
    }
  }
  hi = std::max(hi, lo + 0.5);
  const float height = 60.0f;
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float width = ImGui::GetContentRegionAvail().x;
  const ImVec2 plot_min(origin.x + 34.0f, origin.y + 2.0f);
  const ImVec2 plot_max(origin.x + width - 4.0f, origin.y + height - 2.0f);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(plot_min, plot_max, IM_COL32(30, 32, 37, 255), 3.0f);
  for (int decade = static_cast<int>(std::ceil(lo)); decade <= static_cast<int>(std::floor(hi));
       ++decade) {
    const float y =
        plot_max.y - static_cast<float>((decade - lo) / (hi - lo)) * (plot_max.y - plot_min.y);
    draw->AddLine(ImVec2(plot_min.x, y), ImVec2(plot_max.x, y), IM_COL32(255, 255, 255, 22));
    char text[16];
    std::snprintf(text, sizeof text, "%g", std::pow(10.0, decade));
    draw->AddText(ImVec2(origin.x, y - 7.0f), IM_COL32(150, 155, 165, 255), text);
  }
  const size_t n = snap.history.size();
  for (int line = kLines - 1; line >= 0; --line) {
    std::vector<ImVec2> points;
    for (size_t g = 0; g < n; ++g) {
      const float x =
          plot_min.x + (n == 1 ? 0.5f : static_cast<float>(g) / static_cast<float>(n - 1)) *
                           (plot_max.x - plot_min.x);
      const float y =
          plot_max.y - static_cast<float>((value(snap.history[g], line) - lo) / (hi - lo)) *
                           (plot_max.y - plot_min.y);
      points.emplace_back(x, y);
    }
    if (points.size() == 1) points.push_back(ImVec2(points[0].x + 2.0f, points[0].y));
    draw->AddPolyline(points.data(), static_cast<int>(points.size()), colors[line], 0,
                      line == 0 ? 2.0f : 1.2f);
  }
  ImGui::Dummy(ImVec2(width, height));
  // The legend, in the lines' colours.
  for (int line = 0; line < kLines; ++line) {
    if (line > 0) ImGui::SameLine(0.0f, 8.0f);
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::ColorConvertU32ToFloat4(colors[line]));
    ImGui::TextUnformatted(line == 0 ? "total" : search::fitnessTermName(line - 1));
    ImGui::PopStyleColor();
  }
}

// The settings cannot change under a running search: one line says what they are.
void drawRunningSettings(const EvolutionState& evolution) {
  const search::EvolveSettings& used = evolution.session->settings();
  const std::string budget = budgetText(used);
  ImGui::TextDisabled("%s, population %d, seed %llu, %s, %.0f s window%s",
                      used.optimizer == search::OptimizerKind::kGa ? "GA" : "CMA-ES",
                      evolution.session->population(), static_cast<unsigned long long>(used.seed),
                      budget.c_str(), evolution.session->problem().simulation.seconds,
                      evolution.started.search.no_prior ? ", no prior" : "");
}

// A count of generations, 0..100000, with its tooltip.
void inputGenerations(const char* label, int& generations, int fast_step, const char* tooltip) {
  ImGui::SetNextItemWidth(90.0f);
  ImGui::InputInt(label, &generations, 1, fast_step);
  generations = std::clamp(generations, 0, 100000);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tooltip);
}

// Budget, window, prior, optimiser, population, seed, trials and restarts of the next search.
void drawSearchSettings(EditorState& state) {
  EvolutionState& evolution = state.evolution;
  ImGui::SetNextItemWidth(120.0f);
  float minutes = static_cast<float>(evolution.settings.search.minutes);
  if (ImGui::SliderFloat("minutes", &minutes, 0.5f, 30.0f, "%.1f"))
    evolution.settings.search.minutes = minutes;
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90.0f);
  ImGui::InputInt("generations", &evolution.settings.generations, 1, 10);
  evolution.settings.generations = std::clamp(evolution.settings.generations, 0, 100000);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "The budget in generations (0: the minutes only); the search ends at "
        "whichever comes first");
  ImGui::SetNextItemWidth(100.0f);
  float window = static_cast<float>(evolution.settings.physics.window_s);
  if (ImGui::SliderFloat("window s", &window, 2.0f, 20.0f, "%.0f"))
    evolution.settings.physics.window_s = window;
  ImGui::Checkbox("no prior (baseline)", &evolution.settings.search.no_prior);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90.0f);
  search::OptimizerKind& optimizer = evolution.settings.search.optimizer;
  const bool ga = optimizer == search::OptimizerKind::kGa;
  if (ImGui::BeginCombo("optimiser", ga ? "GA" : "CMA-ES")) {
    if (ImGui::Selectable("CMA-ES", !ga)) optimizer = search::OptimizerKind::kCmaes;
    if (ImGui::Selectable("GA (baseline)", ga)) optimizer = search::OptimizerKind::kGa;
    ImGui::EndCombo();
  }
  // 0 is "the optimiser's default"; the field shows the number the search will use.
  int& population = evolution.settings.search.population;
  // Rebuilt when the project changed, not while a slider is dragged.
  if (population == 0 && !ImGui::IsAnyItemActive()) resolvePopulation(state);
  const int resolved = population > 0 ? population : evolution.resolved_population;
  int shown_population = resolved > 0 ? resolved : population;
  ImGui::SetNextItemWidth(90.0f);
  if (ImGui::InputInt(population > 0 ? "population###population" : "population (auto)###population",
                      &shown_population, 1, 4))
    population = std::clamp(shown_population, 0, 1000);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(population > 0 ? "Individuals per generation (0: the optimiser's default)"
                                     : "The optimiser's default for this clip's %d coordinates "
                                       "(CMA-ES 4 + 3 ln n; GA 32); type a number to set one",
                      evolution.resolved_coordinates);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90.0f);
  int seed = static_cast<int>(evolution.settings.search.seed);
  if (ImGui::InputInt("seed", &seed))
    evolution.settings.search.seed = static_cast<std::uint64_t>(std::max(seed, 0));
  ImGui::SetNextItemWidth(90.0f);
  ImGui::InputInt("trials", &evolution.settings.search.trials, 1, 1);
  evolution.settings.search.trials =
      std::clamp(evolution.settings.search.trials, 1, search::kMaxTrials);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "Runs per individual: the unpushed one and trials - 1 pushed to the left, "
        "right, back and forward; the cost is their mean (slower, sturdier gaits)");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90.0f);
  float robust = static_cast<float>(evolution.settings.search.robust_push_m_s);
  if (ImGui::DragFloat("pushes m/s", &robust, 0.01f, 0.0f, 1.0f, "%.2f"))
    evolution.settings.search.robust_push_m_s = std::clamp(static_cast<double>(robust), 0.0, 10.0);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "Pushes inside every run, per kg of body (0: none; 0.3 is 18 N s on 60 kg): forward, "
        "left, back and right of the clip's travel at 15/35/55/75%% of the window, at no extra "
        "cost");
  inputGenerations("restart after", evolution.settings.search.restart_after, 5,
                   "CMA-ES: start again from the clip's DFT after this many generations "
                   "without a better best, keeping the best (0: never)");
  inputGenerations("try starts", evolution.settings.search.start_generations, 10,
                   "Generations each start is tried (the stance yield off, then at half: legs "
                   "that give on landing); a start whose best walks the whole window is kept at "
                   "once, else the best goes on (0: the first start alone)");
}

// Live: a running search takes them from its next generation.
void drawFitnessWeights(EditorState& state) {
  if (!ImGui::TreeNode("fitness weights")) return;
  bool changed = false;
  for (int k = 0; k < search::kFitnessTermCount; ++k) {
    float w = static_cast<float>(search::fitnessWeight(state.evolution.settings.search.weights, k));
    ImGui::SetNextItemWidth(120.0f);
    if (ImGui::DragFloat(search::fitnessTermName(k), &w, 0.01f, 0.0f, 100.0f, "%.3f")) {
      search::fitnessWeight(state.evolution.settings.search.weights, k) = std::max(w, 0.0f);
      changed = true;
    }
    if (k % 2 == 0 && k + 1 < search::kFitnessTermCount) ImGui::SameLine();
  }
  if (changed) setEvolutionWeights(state);
  ImGui::TreePop();
}

// Start, or pause/resume and stop; whether the viewport shows the population.
void drawRunButtons(EditorState& state, search::SessionState run_state, bool running) {
  EvolutionState& evolution = state.evolution;
  if (!running) {
    if (ImGui::Button(evolution.snapshot ? "Start again" : "Start")) startEvolution(state);
  } else {
    if (run_state == search::SessionState::kPaused) {
      if (ImGui::Button("Resume")) resumeEvolution(state);
    } else if (ImGui::Button("Pause")) {
      pauseEvolution(state);
    }
    ImGui::SameLine();
    if (ImGui::Button("Stop")) stopEvolution(state);
  }
  ImGui::SameLine();
  ImGui::Checkbox("show population", &evolution.show_population);
}

// The chosen run's ghost at the replayed frame: its deviation from the target, the worst joint,
// and every joint's in the tooltip (the viewport's colours in degrees).
void drawGhost(const EditorState& state) {
  const std::optional<Ghost> ghost = currentGhost(state);
  if (!ghost || !state.asset) return;
  const motion::Skeleton& skeleton = state.asset->skeleton;
  const GhostSummary summary = summarise(*ghost);
  if (summary.worst_joint < 0 ||
      ghost->deviation_rad.size() != static_cast<size_t>(skeleton.jointCount()))
    return;
  ImGui::TextWrapped("ghost at %.2f s: off the target by %.1f deg mean, %.1f deg at most (%s)",
                     ghost->time_s, summary.mean_deg, summary.max_deg,
                     skeleton.names[static_cast<size_t>(summary.worst_joint)].c_str());
  if (!ImGui::IsItemHovered()) return;
  ImGui::BeginTooltip();
  ImGui::Text("grey on the target, red at %.0f deg or more off", kGhostRedDeg);
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    ImGui::Text("%-20s %6.1f deg", skeleton.names[static_cast<size_t>(j)].c_str(),
                glm::degrees(ghost->deviation_rad[static_cast<size_t>(j)]));
  }
  ImGui::EndTooltip();
}

// The last generation's runs, best first: a click on one selects it (as a click in the
// viewport does); the chosen one is highlighted.
void drawPopulationList(EvolutionState& evolution) {
  const search::Snapshot& snap = *evolution.snapshot;
  if (snap.population_terms.empty()) return;
  char title[64];
  std::snprintf(title, sizeof title, "runs of generation %d###runs", snap.generation);
  if (!ImGui::TreeNode(title)) return;
  const int chosen = chosenIndividual(evolution);
  const ImGuiTableFlags flags = ImGuiTableFlags_ScrollY | ImGuiTableFlags_RowBg;
  if (ImGui::BeginTable("population", 5, flags, ImVec2(0.0f, 110.0f))) {
    for (const char* column : {"#", "cost", "up s", "m", ""}) ImGui::TableSetupColumn(column);
    ImGui::TableSetupScrollFreeze(0, 1);
    ImGui::TableHeadersRow();
    const std::vector<int> order = rankedIndividuals(snap);
    for (size_t rank = 0; rank < order.size(); ++rank) {
      const int i = order[rank];
      const search::FitnessTerms& t = snap.population_terms[static_cast<size_t>(i)];
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      char label[32];
      std::snprintf(label, sizeof label, "%zu##run%d", rank + 1, i);
      if (ImGui::Selectable(label, i == chosen, ImGuiSelectableFlags_SpanAllColumns))
        selectIndividual(evolution, i);
      ImGui::TableNextColumn();
      ImGui::Text("%.2f", t.total);
      ImGui::TableNextColumn();
      ImGui::Text("%.1f", t.survived_s);
      ImGui::TableNextColumn();
      ImGui::Text("%.1f", t.distance_m);
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(t.diverged ? "diverged" : t.fell ? "fell" : "");
    }
    ImGui::EndTable();
  }
  ImGui::TreePop();
}

// The best run's joints at their torque limit and furthest from the clip (physics/joint_figures.h):
// where an artist looks when it falls or loses the style.
void drawBestJoints(const search::Snapshot& snap, const pipeline::ProjectSettings& started) {
  const std::string limited = physics::torqueLimitLine(snap.best_joints);
  const std::string furthest =
      physics::furthestJointsLine(snap.best_joints, pipeline::trackedName(started));
  if (!limited.empty()) ImGui::TextWrapped("%s", limited.c_str());
  if (!furthest.empty()) ImGui::TextWrapped("%s", furthest.c_str());
}

// The generation, the budget spent, and the terms of the individual clicked in the viewport
// (or the best so far), its ghost's deviation, then the history plot.
void drawProgress(EditorState& state, search::SessionState run_state, bool running) {
  EvolutionState& evolution = state.evolution;
  const search::Snapshot& snap = *evolution.snapshot;
  const double wall = snap.history.empty() ? 0.0 : snap.history.back().wall_s;
  ImGui::Text("%s: generation %d, %lld evaluations, %.0f s (%.1f eval/s)",
              search::sessionStateName(run_state), snap.generation, snap.evaluations, wall,
              wall > 0.0 ? static_cast<double>(snap.evaluations) / wall : 0.0);
  if (!snap.start.empty()) ImGui::TextDisabled("%s", snap.start.c_str());
  if (running && evolution.session) {
    // The budget spent: the larger share of its minutes and of its generations.
    const search::EvolveSettings& used = evolution.session->settings();
    const double budget_s = used.minutes * 60.0;
    const double by_time = budget_s > 0.0 ? std::clamp(wall / budget_s, 0.0, 1.0) : 0.0;
    const double by_generations =
        used.generations > 0 ? std::clamp(double(snap.generation) / used.generations, 0.0, 1.0)
                             : 0.0;
    const double spent = std::max(by_time, by_generations);
    char overlay[96];
    if (used.generations > 0 && budget_s > 0.0)
      std::snprintf(overlay, sizeof overlay, "%.0f / %.0f s, generation %d / %d", wall, budget_s,
                    snap.generation, used.generations);
    else if (used.generations > 0)
      std::snprintf(overlay, sizeof overlay, "generation %d / %d", snap.generation,
                    used.generations);
    else
      std::snprintf(overlay, sizeof overlay, "%.0f / %.0f s of the budget", wall, budget_s);
    ImGui::ProgressBar(static_cast<float>(spent), ImVec2(-1.0f, 0.0f), overlay);
  }
  if (snap.best_point.empty()) return;
  const int picked = evolution.selected;
  const bool show_picked = picked >= 0 && picked < static_cast<int>(snap.population_terms.size());
  const search::FitnessTerms& t =
      show_picked ? snap.population_terms[static_cast<size_t>(picked)] : snap.best_terms;
  if (show_picked) {
    ImGui::TextColored(ImVec4(1.0f, 0.95f, 0.8f, 1.0f), "clicked: #%d of %zu in generation %d",
                       individualRank(snap, picked), snap.population_terms.size(), snap.generation);
    ImGui::SameLine();
    if (ImGui::SmallButton("show the best")) selectIndividual(evolution, -1);
  }
  ImGui::Text("%s: %s %.1f s, %.2f m (%.2f m/s), cost %.2f", show_picked ? "it" : "best",
              t.fell ? "fell after" : "walked", t.survived_s, t.distance_m, t.speed_m_s, t.total);
  if (t.fell && !t.fall_reason.empty())
    ImGui::TextWrapped("why it fell: %s", t.fall_reason.c_str());
  if (!show_picked) drawBestJoints(snap, evolution.started);
  if (ImGui::BeginTable("terms", search::kFitnessTermCount, ImGuiTableFlags_SizingStretchSame)) {
    for (int k = 0; k < search::kFitnessTermCount; ++k)
      ImGui::TableSetupColumn(search::fitnessTermName(k));
    ImGui::TableHeadersRow();
    ImGui::TableNextRow();
    for (int k = 0; k < search::kFitnessTermCount; ++k) {
      ImGui::TableNextColumn();
      ImGui::Text("%.2f", search::fitnessTerm(t, k));
    }
    ImGui::EndTable();
  }
  drawGhost(state);
  drawPopulationList(evolution);
  plotHistory(snap);
}

}  // namespace

void drawEvolvePanel(EditorState& state) {
  ImGui::Begin("Evolve", nullptr, ImGuiWindowFlags_NoCollapse);
  EvolutionState& evolution = state.evolution;
  const search::SessionState run_state =
      evolution.snapshot ? evolution.snapshot->state : search::SessionState::kReady;
  const bool running = search::underWay(run_state);
  if (!state.analysis) {
    ImGui::TextDisabled("Open a clip that analyses to evolve its physical motion.");
    ImGui::End();
    return;
  }
  if (running && evolution.session) {
    drawRunningSettings(evolution);
  } else {
    drawSearchSettings(state);
  }
  drawFitnessWeights(state);
  drawRunButtons(state, run_state, running);
  if (evolution.snapshot) {
    drawProgress(state, run_state, running);
  } else {
    ImGui::TextWrapped(
        "Evolves the clip's Fourier controller (seeded from the model above) until "
        "the simulated character keeps the style without falling.");
  }
  ImGui::End();
}

}  // namespace sinew::editor

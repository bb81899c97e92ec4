// Spectrum: the stride and the model's total error on top, a K slider for all joints and `auto`
// with a tolerance, the joint list (K per joint; or ranked by importance), and for the chosen
// joint its harmonic amplitudes as bars (n = 1..12, rotation axes X/Y/Z in red/green/blue; kept
// harmonics filled, discarded ones outlined) or its curves (original vs model), with its own K
// slider. Every K change re-runs the reconstruction and shows the error live.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <imgui.h>

#include "editor/panels/panels.h"

namespace sinew::editor {
namespace {

constexpr int kBarHarmonics = 12;
constexpr double kDegPerRad = 57.29577951308232;
const ImU32 kAxisColors[3] = {IM_COL32(235, 90, 80, 255), IM_COL32(110, 200, 95, 255),
                              IM_COL32(85, 145, 240, 255)};

bool jointMoves(const spectral::MotionSpectrum& spectrum, int joint) {
  for (const spectral::SignalChannel& channel : spectrum.signals.channels) {
    if (channel.joint == joint) return true;
  }
  return false;
}

void drawBars(const EditorState& state, int joint) {
  const AnalysisState& analysis = *state.analysis;
  const spectral::MotionSpectrum& spectrum = analysis.spectrum;
  const int k = analysis.joint_k[static_cast<size_t>(joint)];
  // Per axis: amplitudes (degrees) of n = 1..12 and whether each is kept.
  double amplitude[3][kBarHarmonics] = {};
  bool kept[3][kBarHarmonics] = {};
  bool has_axis[3] = {};
  double top = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const int c = spectrum.signals.find(joint, spectral::SignalKind::kRotation, axis);
    if (c < 0) continue;
    has_axis[axis] = true;
    const spectral::HarmonicSeries& series = spectrum.series[static_cast<size_t>(c)];
    for (const spectral::Harmonic& h : series.harmonics) {
      if (h.n < 1 || h.n > kBarHarmonics) continue;
      amplitude[axis][h.n - 1] = h.amplitude * kDegPerRad;
      top = std::max(top, amplitude[axis][h.n - 1]);
    }
    for (const spectral::Harmonic& h : series.strongest(k)) {
      if (h.n >= 1 && h.n <= kBarHarmonics) kept[axis][h.n - 1] = true;
    }
  }
  if (!has_axis[0] && !has_axis[1] && !has_axis[2]) {
    ImGui::TextDisabled("This joint does not rotate in this clip.");
    return;
  }
  top = std::max(top, 1e-3);

  const float height = std::clamp(ImGui::GetContentRegionAvail().y - 4.0f, 120.0f, 300.0f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float width = ImGui::GetContentRegionAvail().x;
  const float left = 44.0f, bottom = 20.0f, top_pad = 8.0f;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 plot_min(origin.x + left, origin.y + top_pad);
  const ImVec2 plot_max(origin.x + width - 4.0f, origin.y + height - bottom);
  draw->AddRectFilled(plot_min, plot_max, IM_COL32(30, 32, 37, 255), 3.0f);
  const float plot_h = plot_max.y - plot_min.y;
  // Horizontal guides at quarters of the largest amplitude, labelled in degrees.
  for (int q = 0; q <= 4; ++q) {
    const float y = plot_max.y - plot_h * q / 4.0f;
    draw->AddLine(ImVec2(plot_min.x, y), ImVec2(plot_max.x, y),
                  IM_COL32(255, 255, 255, q ? 18 : 50));
    char text[32];
    std::snprintf(text, sizeof text, "%.1f°", top * q / 4.0);
    draw->AddText(ImVec2(origin.x, y - 7.0f), IM_COL32(150, 155, 165, 255), text);
  }
  const float group = (plot_max.x - plot_min.x) / kBarHarmonics;
  const float bar = group * 0.29f;
  for (int n = 0; n < kBarHarmonics; ++n) {
    const float gx = plot_min.x + group * n + group * 0.5f - 1.5f * bar;
    for (int axis = 0; axis < 3; ++axis) {
      if (!has_axis[axis]) continue;
      const float h = static_cast<float>(amplitude[axis][n] / top) * plot_h;
      const ImVec2 a(gx + axis * bar + 1.0f, plot_max.y - std::max(h, 1.0f));
      const ImVec2 b(gx + (axis + 1) * bar - 1.0f, plot_max.y);
      if (kept[axis][n]) {
        draw->AddRectFilled(a, b, kAxisColors[axis], 1.5f);
      } else {
        draw->AddRect(a, b, kAxisColors[axis] & IM_COL32(255, 255, 255, 170), 1.5f, 0, 1.2f);
      }
    }
    char label[8];
    std::snprintf(label, sizeof label, "%d", n + 1);
    const ImVec2 size = ImGui::CalcTextSize(label);
    draw->AddText(ImVec2(plot_min.x + group * (n + 0.5f) - size.x * 0.5f, plot_max.y + 3.0f),
                  IM_COL32(170, 175, 185, 255), label);
  }
  ImGui::Dummy(ImVec2(width, height));
}

// The chosen joint's rotation channels over the analysed window: the original (solid) and the
// model with the joint's K (dashed look: thinner, brighter), degrees, per axis in its colour.
void drawCurves(const EditorState& state, int joint) {
  const AnalysisState& analysis = *state.analysis;
  const spectral::MotionSpectrum& spectrum = analysis.spectrum;
  const int k = analysis.joint_k[static_cast<size_t>(joint)];
  const double dt = spectrum.signals.frame_time;
  const double start = spectrum.window.start_s;
  // The frames the model fits; plain names, not a structured binding, so that the lambdas below
  // may capture them (clang 14 refuses captured bindings).
  const auto range = spectral::windowFrameRange(spectrum);
  const auto first = range.first;
  const auto last = range.second;
  if (last <= first) return;
  struct Curve {
    std::vector<ImVec2> original, model;
    int axis;
  };
  std::vector<Curve> curves;
  double lo = 1e30, hi = -1e30;
  for (int axis = 0; axis < 3; ++axis) {
    const int c = spectrum.signals.find(joint, spectral::SignalKind::kRotation, axis);
    if (c < 0) continue;
    const spectral::SignalChannel& channel = spectrum.signals.channels[static_cast<size_t>(c)];
    const spectral::HarmonicSeries& series = spectrum.series[static_cast<size_t>(c)];
    const std::vector<spectral::Harmonic> terms = series.strongest(k);
    Curve curve{{}, {}, axis};
    for (int f = first; f <= last; ++f) {
      const double t = f * dt;
      const double o = channel.values[static_cast<size_t>(f)] * kDegPerRad;
      const double m =
          spectral::evaluate(series.mean, terms, spectrum.omega0, t - start) * kDegPerRad;
      curve.original.emplace_back(static_cast<float>(t), static_cast<float>(o));
      curve.model.emplace_back(static_cast<float>(t), static_cast<float>(m));
      lo = std::min({lo, o, m});
      hi = std::max({hi, o, m});
    }
    curves.push_back(std::move(curve));
  }
  if (curves.empty()) {
    ImGui::TextDisabled("This joint does not rotate in this clip.");
    return;
  }
  if (hi - lo < 1e-3) hi = lo + 1e-3;
  const float height = std::clamp(ImGui::GetContentRegionAvail().y - 4.0f, 120.0f, 300.0f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float width = ImGui::GetContentRegionAvail().x;
  const ImVec2 plot_min(origin.x + 44.0f, origin.y + 8.0f);
  const ImVec2 plot_max(origin.x + width - 4.0f, origin.y + height - 20.0f);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(plot_min, plot_max, IM_COL32(30, 32, 37, 255), 3.0f);
  auto at = [&](ImVec2 p) {
    const float x = plot_min.x + (p.x - static_cast<float>(first * dt)) /
                                     static_cast<float>((last - first) * dt) *
                                     (plot_max.x - plot_min.x);
    const float y =
        plot_max.y - static_cast<float>((p.y - lo) / (hi - lo)) * (plot_max.y - plot_min.y);
    return ImVec2(x, y);
  };
  for (int q = 0; q <= 2; ++q) {
    const double value = lo + (hi - lo) * q / 2.0;
    const float y = plot_max.y - (plot_max.y - plot_min.y) * q / 2.0f;
    draw->AddLine(ImVec2(plot_min.x, y), ImVec2(plot_max.x, y), IM_COL32(255, 255, 255, 25));
    char text[32];
    std::snprintf(text, sizeof text, "%.0f°", value);
    draw->AddText(ImVec2(origin.x, y - 7.0f), IM_COL32(150, 155, 165, 255), text);
  }
  for (const Curve& curve : curves) {
    std::vector<ImVec2> points;
    for (const ImVec2& p : curve.original) points.push_back(at(p));
    draw->AddPolyline(points.data(), static_cast<int>(points.size()),
                      kAxisColors[curve.axis] & IM_COL32(255, 255, 255, 120), 0, 3.0f);
    points.clear();
    for (const ImVec2& p : curve.model) points.push_back(at(p));
    draw->AddPolyline(points.data(), static_cast<int>(points.size()), IM_COL32(240, 240, 240, 230),
                      0, 1.2f);
  }
  char text[96];
  std::snprintf(text, sizeof text, "%.2f s .. %.2f s, model K = %d", first * dt, last * dt, k);
  draw->AddText(ImVec2(plot_min.x, plot_max.y + 3.0f), IM_COL32(170, 175, 185, 255), text);
  ImGui::Dummy(ImVec2(width, height));
}

// The joints ranked by the position error their freezing would cost: the paper's "which joints
// could be removed". Click one to choose it.
void drawRanking(EditorState& state) {
  const spectral::ImportanceReport* report = rankJoints(state);
  if (report == nullptr) return;
  const motion::Skeleton& skeleton = state.asset->skeleton;
  ImGui::TextDisabled("frozen: cm mean");
  for (const spectral::JointImportance& j : report->joints) {
    char label[160];
    std::snprintf(label, sizeof label, "%-14s %5.2f",
                  skeleton.names[static_cast<size_t>(j.joint)].c_str(), j.frozen_cm_mean);
    if (ImGui::Selectable(label, state.selected_joint == j.joint)) state.selected_joint = j.joint;
    if (ImGui::IsItemHovered()) {
      ImGui::SetTooltip(
          "Frozen at its mean, the motion is off by %.2f cm on average (%.2f cm at "
          "worst); the model itself is off by %.2f cm",
          j.frozen_cm_mean, j.frozen_cm_max, report->model_cm_mean);
    }
  }
}

// The stride, the model's error and size, and K for every joint (a number, or auto within a
// tolerance).
void drawSummary(EditorState& state, SpectrumPanelState& panel) {
  AnalysisState& analysis = *state.analysis;
  const spectral::MotionSpectrum& spectrum = analysis.spectrum;
  if (spectrum.stride.found) {
    ImGui::Text("Stride %.3f s (%.2f Hz)", spectrum.period_s, 1.0 / spectrum.period_s);
    ImGui::SameLine();
    ImGui::TextDisabled("similarity %.2f, window %.2f s + %d stride(s)", spectrum.stride.similarity,
                        spectrum.window.start_s, spectrum.window.strides);
  } else {
    ImGui::TextColored(ImVec4(1.0f, 0.78f, 0.35f, 1.0f),
                       "No stride: whole clip as one cycle (%.2f s)", spectrum.period_s);
  }
  const spectral::JointError& total = analysis.total;
  ImGui::Text("Model error  %.2f° RMS   %.2f cm mean   %.2f cm max", total.rot_err_deg_rms,
              total.pos_err_cm_mean, total.pos_err_cm_max);
  int coefficients = 0;
  for (const spectral::SignalChannel& channel : spectrum.signals.channels) {
    coefficients += 1 + 2 * analysis.joint_k[static_cast<size_t>(channel.joint)];
  }
  ImGui::TextDisabled("%d coefficients over %zu channels", coefficients,
                      spectrum.signals.channels.size());
  ImGui::SetNextItemWidth(std::max(ImGui::GetContentRegionAvail().x - 290.0f, 80.0f));
  if (ImGui::SliderInt("K all joints", &panel.global_k, 0, kMaxK)) {
    setJointK(state, std::vector<int>(analysis.joint_k.size(), panel.global_k));
  }
  ImGui::SameLine();
  if (ImGui::Button("auto")) setAutoK(state, panel.tolerance_cm);
  if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip("The fewest harmonics per joint keeping every joint within the tolerance");
  }
  ImGui::SameLine();
  ImGui::SetNextItemWidth(70.0f);
  ImGui::DragFloat("cm", &panel.tolerance_cm, 0.05f, 0.1f, 10.0f, "%.2f");
}

// The joint list (the skeleton's tree, or ranked by what freezing each joint would cost).
void drawJointList(EditorState& state, SpectrumPanelState& panel, float list_w) {
  const motion::Skeleton& skeleton = state.asset->skeleton;
  const AnalysisState& analysis = *state.analysis;
  ImGui::BeginChild("##joints", ImVec2(list_w, 0), true);
  ImGui::Checkbox("ranked", &panel.show_ranking);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("By what freezing each joint would cost");
  if (!panel.show_ranking) {
    ImGui::SameLine();
    ImGui::Checkbox("moving", &panel.joints_moving_only);
  }
  if (panel.show_ranking) drawRanking(state);
  for (int j = 0; j < skeleton.jointCount() && !panel.show_ranking; ++j) {
    const bool moves = jointMoves(analysis.spectrum, j);
    if (panel.joints_moving_only && !moves) continue;
    char label[160];
    std::snprintf(label, sizeof label, "%*s%s", 2 * std::min(skeleton.depth(j), 8), "",
                  skeleton.names[static_cast<size_t>(j)].c_str());
    if (!moves)
      ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    if (ImGui::Selectable(label, state.selected_joint == j)) state.selected_joint = j;
    if (!moves) ImGui::PopStyleColor();
    if (moves) {
      ImGui::SameLine(list_w - 48.0f);
      ImGui::TextDisabled("K%d", analysis.joint_k[static_cast<size_t>(j)]);
    }
  }
  ImGui::EndChild();
}

// The chosen joint: its K, its error, and its curves or harmonic bars.
void drawJointDetail(EditorState& state, SpectrumPanelState& panel) {
  const motion::Skeleton& skeleton = state.asset->skeleton;
  const AnalysisState& analysis = *state.analysis;
  ImGui::BeginChild("##joint", ImVec2(0, 0), false);
  const int joint = std::clamp(state.selected_joint, 0, skeleton.jointCount() - 1);
  ImGui::Text("%s", skeleton.names[static_cast<size_t>(joint)].c_str());
  ImGui::SameLine(std::max(ImGui::GetContentRegionAvail().x - 70.0f, 80.0f));
  ImGui::Checkbox("curves", &panel.show_curves);
  int k = analysis.joint_k[static_cast<size_t>(joint)];
  ImGui::SetNextItemWidth(-30.0f);
  if (ImGui::SliderInt("K", &k, 0, kMaxK)) {
    std::vector<int> joint_k = analysis.joint_k;
    joint_k[static_cast<size_t>(joint)] = k;
    setJointK(state, std::move(joint_k));
  }
  const spectral::JointError& error = state.analysis->errors[static_cast<size_t>(joint)];
  ImGui::Text("%.2f° RMS  (max %.2f°)", error.rot_err_deg_rms, error.rot_err_deg_max);
  ImGui::Text("%.2f cm mean  (max %.2f cm)", error.pos_err_cm_mean, error.pos_err_cm_max);
  ImGui::TextColored(ImVec4(0.92f, 0.35f, 0.31f, 1.0f), "X");
  ImGui::SameLine();
  ImGui::TextColored(ImVec4(0.43f, 0.78f, 0.37f, 1.0f), "Y");
  ImGui::SameLine();
  ImGui::TextColored(ImVec4(0.33f, 0.57f, 0.94f, 1.0f), "Z");
  ImGui::SameLine();
  ImGui::TextDisabled(panel.show_curves ? " original wide, model white"
                                        : " filled kept, outlined dropped");
  if (panel.show_curves) {
    drawCurves(state, joint);
  } else {
    drawBars(state, joint);
  }
  ImGui::EndChild();
}

}  // namespace

void drawSpectrumPanel(EditorState& state, SpectrumPanelState& panel, int& tab) {
  if (!ImGui::Begin("Spectrum", nullptr, ImGuiWindowFlags_NoCollapse)) {
    ImGui::End();
    return;
  }
  drawRightTabs(tab);
  if (!state.analysis || state.clip() == nullptr) {
    ImGui::TextDisabled(state.clip() == nullptr ? "Open a clip to see its spectrum."
                                                : "This clip could not be analysed (see Log).");
    ImGui::End();
    return;
  }
  drawSummary(state, panel);
  ImGui::Separator();
  // Left: the joint list. Right: the chosen joint.
  drawJointList(state, panel, 190.0f);
  ImGui::SameLine();
  drawJointDetail(state, panel);
  ImGui::End();
}

}  // namespace sinew::editor

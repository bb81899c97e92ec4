// sinew analyze: the indirect figures (feet, contacts, steps, centre of mass) and the joint
// importance ranking, as a table after the harmonics and as JSON keys beside them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/analysis.h"
#include "sinew/spectral/importance.h"
#include "sinew/spectral/indirect.h"

namespace sinew::app {

// Either part may be missing (a rig with no feet has no contacts) without failing the command;
// `problems` says why.
struct IndirectReport {
  std::optional<spectral::IndirectSignals> indirect;
  std::optional<spectral::ImportanceReport> importance;
  std::vector<std::string> problems;
};

// Measures both for `clip`, whose analysis is `spectrum`, with the default settings.
IndirectReport measureIndirect(const motion::Skeleton& skeleton, const motion::Clip& clip,
                               const spectral::MotionSpectrum& spectrum);

// The table for people: feet, stride from contacts against the analysis, steps, centre of mass,
// the ten most important joints.
void printIndirect(const motion::Skeleton& skeleton, const IndirectReport& report);

// An object with the keys "foot_contacts", "steps", "centre_of_mass", "importance" and
// "indirect_notes", to merge into the analyze JSON (json.update(...)). Lengths in metres, times
// in seconds, errors in centimetres, as the key names say.
nlohmann::json indirectJson(const motion::Skeleton& skeleton, const IndirectReport& report);

}  // namespace sinew::app

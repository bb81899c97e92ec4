// TargetMotion coefficients as JSON: what an artist edited, loadable back onto the same skeleton
// (joints matched by name). Format "sinew.target", version 1; see docs/file_formats.md.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::spectral {

std::string targetToJson(const TargetMotion& target, const motion::Skeleton& skeleton);

// `source_name` is used in messages, which name the field ("walk.json: channels[3].axis: ...").
// Joints are matched by name and parent (files without parents, by name); numbers are checked
// against spectral/limits.h. Unknown keys are reported in `warnings` (nullable) with the field.
Result<TargetMotion> targetFromJson(std::string_view text, const motion::Skeleton& skeleton,
                                    std::string_view source_name,
                                    std::vector<std::string>* warnings = nullptr);

Status saveTarget(const std::filesystem::path& path, const TargetMotion& target,
                  const motion::Skeleton& skeleton);
Result<TargetMotion> loadTarget(const std::filesystem::path& path, const motion::Skeleton& skeleton,
                                std::vector<std::string>* warnings = nullptr);

}  // namespace sinew::spectral

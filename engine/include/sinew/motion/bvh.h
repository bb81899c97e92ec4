// Biovision Hierarchy (BVH) reading and writing.
// Reads what real files contain: any of the six Euler orders per joint (mixed in one file), 3- and
// 6-channel joints, End Sites, CRLF/LF/mixed line endings, tabs, scientific notation, numbers like
// ".0083333", trailing spaces, names with ':' (Mixamo). Refuses malformed files with
// "<file>:<line>: <what was expected>"; never crashes, never hangs (linear time, no recursion).
#pragma once

#include <string>
#include <string_view>

#include "sinew/core/status.h"
#include "sinew/motion/asset.h"

namespace sinew::motion {

// `source_name` is used only in messages. Units and up axis are detected unless `options` set them.
Result<MotionAsset> readBvh(std::string_view text, std::string_view source_name,
                            const ImportOptions& options = {});

// The units and axes a BVH export of this skeleton uses unless told otherwise: the source file's
// for a rig that came from BVH (so a round trip writes the numbers it read), else centimetres,
// Y-up, what most BVH tools expect.
SourceFrame defaultBvhFrame(const Skeleton& skeleton);

// BVH text for `clip` on `skeleton`, in `frame` units and axes. Joints keep their channel layout;
// joints without one get 3 rotation channels ZXY, plus 3 position channels for roots and for
// joints whose translation moves. Numbers are written in their shortest exact form.
std::string writeBvh(const Skeleton& skeleton, const Clip& clip, const SourceFrame& frame);

}  // namespace sinew::motion

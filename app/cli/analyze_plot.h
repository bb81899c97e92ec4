// sinew analyze --plot FILE: the spectrum plot (sinew/spectral/plot.h) written as SVG, or as PNG
// through rsvg-convert (Debian's librsvg2-bin) when that is installed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/analysis.h"

namespace sinew::app {

// Writes the plot of `joint_names` (empty: the four that rotate most) to `path`, atomically. The
// format follows the extension: .svg, or .png (converted by rsvg-convert; without it the message
// says to install librsvg2-bin or write .svg). The message names the path, the joint or the tool.
Status writePlot(const std::filesystem::path& path, const motion::Skeleton& skeleton,
                 const motion::Clip& clip, const spectral::MotionSpectrum& spectrum,
                 const std::vector<std::string>& joint_names);

}  // namespace sinew::app

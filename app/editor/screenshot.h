// Saves the current GL framebuffer as a PNG (rows flipped to top-down).
#pragma once

#include <string>

#include "sinew/core/status.h"

namespace sinew::editor {

Status saveFramebufferPng(const std::string& path, int width, int height);
// A part of the framebuffer: (x, y) is its top-left corner counted from the window's top-left,
// in framebuffer pixels; clipped to the framebuffer.
Status saveFramebufferRegionPng(const std::string& path, int fb_width, int fb_height, int x, int y,
                                int width, int height);

}  // namespace sinew::editor

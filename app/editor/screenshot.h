// Saves the current GL framebuffer as a PNG (rows flipped to top-down).
#pragma once

#include <string>

#include "sinew/core/status.h"

namespace sinew::editor {

Status saveFramebufferPng(const std::string& path, int width, int height);

}  // namespace sinew::editor

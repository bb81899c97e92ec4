#include "editor/screenshot.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include <stb_image_write.h>

#include "editor/gl.h"

namespace sinew::editor {

Status saveFramebufferRegionPng(const std::string& path, int fb_width, int fb_height, int x, int y,
                                int width, int height) {
  x = std::clamp(x, 0, std::max(fb_width, 0));
  y = std::clamp(y, 0, std::max(fb_height, 0));
  width = std::min(width, fb_width - x);
  height = std::min(height, fb_height - y);
  if (width <= 0 || height <= 0) return Status::error(path + ": the region has no pixels");
  const size_t row = static_cast<size_t>(width) * 3;
  std::vector<unsigned char> pixels(row * static_cast<size_t>(height));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  // GL counts rows from the bottom.
  glReadPixels(x, fb_height - y - height, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  std::vector<unsigned char> flipped(pixels.size());
  for (int r = 0; r < height; ++r) {
    std::memcpy(&flipped[row * static_cast<size_t>(r)],
                &pixels[row * static_cast<size_t>(height - 1 - r)], row);
  }
  if (stbi_write_png(path.c_str(), width, height, 3, flipped.data(), static_cast<int>(row)) == 0) {
    return Status::error(path + ": could not write the screenshot");
  }
  return {};
}

Status saveFramebufferPng(const std::string& path, int width, int height) {
  if (width <= 0 || height <= 0) return Status::error("screenshot: the window has no pixels");
  return saveFramebufferRegionPng(path, width, height, 0, 0, width, height);
}

}  // namespace sinew::editor

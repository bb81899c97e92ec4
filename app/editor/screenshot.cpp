#include "editor/screenshot.h"

#include <cstring>
#include <vector>

#include <stb_image_write.h>

#include "editor/gl.h"

namespace sinew::editor {

Status saveFramebufferPng(const std::string& path, int width, int height) {
  if (width <= 0 || height <= 0) return Status::error("screenshot: the window has no pixels");
  const size_t row = static_cast<size_t>(width) * 3;
  std::vector<unsigned char> pixels(row * static_cast<size_t>(height));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  std::vector<unsigned char> flipped(pixels.size());
  for (int y = 0; y < height; ++y) {
    std::memcpy(&flipped[row * static_cast<size_t>(y)],
                &pixels[row * static_cast<size_t>(height - 1 - y)], row);
  }
  if (stbi_write_png(path.c_str(), width, height, 3, flipped.data(), static_cast<int>(row)) == 0) {
    return Status::error(path + ": could not write the screenshot");
  }
  return {};
}

}  // namespace sinew::editor

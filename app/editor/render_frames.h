// `sinew render`: a motion drawn frame by frame into PNG files for review (dailies, a contact
// sheet, a turntable), with the editor's renderer and camera but no panels.
#pragma once

#include <string>

namespace sinew::editor {

struct RenderOptions {
  std::string file;        // a .bvh/.glb/.gltf motion (an evolved best.bvh too) or a project
  std::string animation;   // the clip in a glTF with several; empty: the first
  std::string out_dir;     // frame_0001.png, frame_0002.png, ...
  int width = 960, height = 540;
  double fps = 0.0;        // frames per second of the render; 0: the clip's own
  bool turntable = false;  // the camera goes once around the character over the clip
  bool show_model = false; // draw the harmonic model beside the clip too
  std::string shader_dir;
};

// Returns the process exit code: 0, or 1 with a message on stderr (no display, a file that does
// not load, a frame that cannot be written).
int renderFrames(const RenderOptions& options);

}  // namespace sinew::editor

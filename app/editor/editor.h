// The editor: a GLFW window with Dear ImGui panels around an OpenGL viewport.
#pragma once

#include <string>

namespace sinew::editor {

struct EditorOptions {
  std::string file;             // opened at start; empty: none
  std::string animation;        // the animation to choose in `file` (glTF); empty: the first
  std::string screenshot;       // when set: render `frames` frames, save the window here, exit
  int frames = 30;              // frames rendered before the screenshot, >= 1
  std::string shader_dir;       // where the GLSL files are
  bool evolve = false;          // start the search on the opened clip at once
  double evolve_minutes = 2.0;  // its budget
  int evolve_generations = 0;   // with a screenshot: frames count only once the search has
                                // finished this many generations (waiting at most 2 minutes)
  int shown = 8;                // individuals of the population drawn, best first
  std::string panel_dir;        // with a screenshot: also each panel as DIR/<panel>.png
  bool bench = false;           // print frame times: `frames` frames of the clip alone, then
                                // `frames` frames with the population while the search runs
  bool shadows = true;          // the view's Shadows toggle at start
  bool mesh = true;             // the view's Mesh toggle at start (glTF skinned meshes)
  std::string export_dir;       // with `evolve`: no window; run the search on the editor's model
                                // (`evolve_generations` generations, else `evolve_minutes`),
                                // write what `sinew evolve --out` writes here, and exit
};

// Runs until the window closes (or the screenshot is written). Returns the process exit code:
// 0, or 1 when no window could be made or the screenshot could not be written. A file that does
// not load is reported in the Log panel (and on stdout), not as a failure.
int runEditor(const EditorOptions& options);

// The editor's model without a window (`export_dir`): opens `file`, evolves, writes the results.
// Returns 0, or 1 when the project does not open, the search does not start or the results are
// not written (the log says why on stdout).
int runHeadlessEvolve(const EditorOptions& options);

}  // namespace sinew::editor

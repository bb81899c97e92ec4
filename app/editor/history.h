// Undo and redo over the editor's settings. The whole of what a user sets (files, K per joint,
// the search's settings and weights, physics, view) is one value, an app::Project; the history
// keeps the values before each change. The main loop calls record() each frame while no widget is
// being dragged, so a slider drag is one step and every setting is covered without each panel
// having to announce its changes.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "project/project.h"

namespace sinew::editor {

class History {
 public:
  explicit History(size_t limit = 200) : limit_(limit) {}

  // Starts over from `current` (after opening a project or a file): nothing to undo or redo.
  void reset(app::Project current);
  // Records `current` as one step when it differs from the last recorded value; clears redo.
  // Returns whether it did.
  bool record(const app::Project& current);
  // The value to go back to (and what the step changed), or nothing when there is none.
  struct Step {
    app::Project value;
    std::string what;  // "K of LeftUpLeg 5 -> 3"
  };
  std::optional<Step> undo();
  std::optional<Step> redo();

  bool canUndo() const { return !undo_.empty(); }
  bool canRedo() const { return !redo_.empty(); }
  // What undo / redo would change, for menus ("" when nothing).
  std::string undoLabel() const;
  std::string redoLabel() const;
  const app::Project& current() const { return current_; }

 private:
  std::vector<app::Project> undo_, redo_;  // oldest first; the back is the next to apply
  app::Project current_;
  size_t limit_;
};

// A short description of what differs between two values, for the log and the menus:
// "K of LeftUpLeg 5 -> 3", "search weight fall 10 -> 4", "opened walk.bvh", "3 settings".
std::string describeChange(const app::Project& before, const app::Project& after);

}  // namespace sinew::editor

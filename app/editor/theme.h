// The editor's look: a dark, low-contrast theme with one warm accent, and a readable font.
#pragma once

namespace sinew::editor {

void applyTheme();  // needs a current ImGui context, before the first frame

}  // namespace sinew::editor

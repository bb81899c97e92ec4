// Whole-file reads and crash-safe writes. A failed save never destroys the previous file: bytes go
// to a temporary file beside the target, which is flushed and then renamed over it.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "sinew/core/status.h"

namespace sinew {

// The file's bytes; the message names the path and the reason ("no such file", ...).
Result<std::string> readFile(const std::filesystem::path& path);

// Writes via "<path>.tmp-<pid>" and rename; on failure the temporary is removed and any existing
// file at `path` is untouched.
Status writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

}  // namespace sinew

// glTF 2.0 (.glb and .gltf) reading and writing, through tinygltf.
#pragma once

#include <filesystem>
#include <string>

#include "sinew/core/status.h"
#include "sinew/motion/asset.h"

namespace sinew::motion {

// Imports the node hierarchy of the first skin (plus its ancestors, so world transforms are
// right), inverse bind matrices, skinned meshes with joint weights, and every animation
// (translation, rotation, scale; LINEAR, STEP, CUBICSPLINE), resampled to options.fps or to each
// animation's median key spacing. A file without skins uses the whole node tree.
Result<MotionAsset> loadGltf(const std::filesystem::path& path, const ImportOptions& options = {});
// The same from a file's bytes already in memory; `path` names it in messages and is where a
// .gltf's external buffers are looked for.
Result<MotionAsset> readGltf(std::string bytes, const std::filesystem::path& path,
                             const ImportOptions& options = {});

// Writes `clip` as a .glb or .gltf (by extension). When asset.gltf is set the original document
// is kept (meshes, skins, materials, textures) and its animations are replaced by `clip`;
// otherwise a new document is built: the joint hierarchy, a skin and a simple bone mesh so that
// Blender, Maya, Unity and Unreal import an armature.
Status saveGltf(const std::filesystem::path& path, const MotionAsset& asset, const Clip& clip);

}  // namespace sinew::motion

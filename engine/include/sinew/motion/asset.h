// What one motion file gives the engine: a skeleton, its clips, and (glTF) skinned meshes.
// importMotion/exportMotion pick BVH or glTF by the file extension.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/glitch.h"
#include "sinew/motion/skeleton.h"
#include "sinew/motion/units.h"

namespace sinew::motion {

// A skinned triangle mesh as the editor draws it (float, as the GPU wants it).
struct SkinnedMesh {
  std::string name;
  std::vector<glm::vec3> positions;    // (vertices) bind pose in the mesh node's space, metres
                                       // once mesh_to_world places them (glTF ignores the node
                                       // for skinning: the inverse binds hold it)
  std::vector<glm::vec3> normals;      // (vertices) unit length, or empty
  std::vector<glm::u16vec4> joints;    // (vertices) skeleton joint indices of the four influences
  std::vector<glm::vec4> weights;      // (vertices) influence weights, summing to 1
  std::vector<std::uint32_t> indices;  // (3 x triangles) into the vertex arrays
  std::vector<glm::dmat4> inverse_bind;  // (skeleton joints) bind-pose world -> joint space;
                                         // identity for joints the skin does not use
  glm::dmat4 mesh_to_world{1.0};       // the mesh node's world transform at bind time
};

// The original glTF document, kept so that export can write the same mesh, skin, materials and
// textures with a new animation. Immutable once imported; shared between copies of an asset.
struct GltfSource {
  std::string bytes;                // the file as read (.glb or .gltf JSON with embedded buffers)
  bool binary = true;               // .glb
  std::filesystem::path directory;  // for .gltf files that reference external buffers/images
  std::vector<int> node_of_joint;   // (skeleton joints) the glTF node index of each joint
  int skin_count = 0;               // skins in the file (the first one is imported)
  // How the reader turned the file's numbers into metres, so that export writes the file's own
  // numbers back (gltf_units.h). Empty: the numbers were metres as they stand.
  std::vector<double> metres_per_number;  // (skeleton joints) factor applied to each joint's
                                          // translations: the folded scales above it, times the
                                          // unit's metres
  std::vector<double> folded_scale;       // (skeleton joints) the uniform rest scale folded out
                                          // of each joint (an armature's 0.01), 1 elsewhere
};

struct ImportOptions {
  std::optional<LengthUnit> unit;  // override the detected unit (glTF: of the numbers left once
                                   // the armature's scale is applied)
  std::optional<UpAxis> up;        // BVH: override the detected up axis (glTF is Y-up)
  std::optional<double> fps;       // glTF: resampling rate; default: each animation's median
                                   // key spacing. Must be in (0, 1000].
  bool repair_glitches = true;     // repair the glitches found (glitch.h); false keeps them
  GlitchSettings glitch;           // what counts as a glitch
};

struct MotionAsset {
  std::filesystem::path path;           // where it was read from (for messages)
  Skeleton skeleton;
  std::vector<Clip> clips;              // BVH: one; glTF: one per animation, in file order
  std::vector<SkinnedMesh> meshes;      // glTF skinned meshes; empty for BVH
  FrameDetection detection;             // units and up axis, and why
  std::vector<std::string> warnings;    // things the user should know; nothing was lost silently
  std::vector<std::vector<Glitch>> glitches;  // (clips) rotation glitches found on import
  bool glitches_repaired = false;       // they were repaired (ImportOptions::repair_glitches)
  std::shared_ptr<const GltfSource> gltf;  // set when the rig came from glTF

  // Index of the clip with that name, or -1.
  int findClip(const std::string& name) const;
};

// Reads a .bvh, .glb or .gltf file. Every failure names the file, and for text formats the line.
// Rotation glitches are found in every clip, listed in `glitches` and the warnings, and (by
// default) repaired.
Result<MotionAsset> importMotion(const std::filesystem::path& path, const ImportOptions& options = {});

struct ExportOptions {
  // BVH: the frame and units to write; default the skeleton's source frame (so a BVH round trip
  // writes the numbers it read) and centimetres, Y-up for rigs that did not come from BVH.
  std::optional<SourceFrame> bvh_frame;
  std::optional<double> fps;  // resample the clip to this rate before writing; default: as is
};

// Writes `clip` on `asset`'s skeleton as .bvh, .glb or .gltf (by extension), atomically.
// glTF export includes the original mesh and skin when the asset came from glTF.
Status exportMotion(const std::filesystem::path& path, const MotionAsset& asset, const Clip& clip,
                    const ExportOptions& options = {});

// Resamples a clip to a new frame time: rotations by slerp, translations and scales linearly.
// The last frame stays at (or just before) the original duration.
Clip resampleClip(const Clip& clip, double frame_time);

}  // namespace sinew::motion

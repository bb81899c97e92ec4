// glTF lengths in metres. glTF is metres by specification, but the numbers in a file are not
// always metres: a Blender armature scaled 0.01 over centimetre bones renders in metres only
// through that node scale, and the Khronos Fox is centimetres with no scale at all. The reader
// builds the asset from the file's numbers; toMetres then makes them metres wherever the engine
// reads them (offsets and translation channels, which physics reads without scales; mesh
// vertices and inverse bind matrices, which the editor skins) and records the factors, so that
// export writes the file's own numbers back. Internal to the engine.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "sinew/motion/asset.h"

namespace sinew::motion::gltf {

// (joints) The uniform rest scale to fold out of each joint, 1 elsewhere: the scales on the
// joints from the root down to the pelvis (pelvisJoint), where an armature or skeleton root
// sits. A scale that any clip animates, or that is not uniform, stays where it is.
std::vector<double> foldableScales(const Skeleton& skeleton, const std::vector<Clip>& clips);

// Moves each folded scale into the translations below it: every joint's rest and animated
// translation times the folded scales of its ancestors, the folded joints' scales 1, and each
// inverse bind matrix pre-multiplied by the scales of its joint and the joint's ancestors, so
// every joint and skinned vertex stays where it was in the world. Returns (joints) the factor
// applied to each joint's translations.
std::vector<double> foldScales(MotionAsset& asset, const std::vector<double>& folded);

// Multiplies every length by `metres_per_number`: offsets, translations, mesh vertices, and
// the translation parts of the inverse bind matrices and mesh_to_world.
void scaleLengths(MotionAsset& asset, double metres_per_number);

// The whole step, after the reader has built the skeleton, clips and meshes from the file's
// numbers: folds the armature's scale, chooses the unit (options.unit, else detectStatedFrame:
// metres unless the figure is implausible in metres), scales, and fills asset.detection,
// skeleton.source and the factors in `source`.
void toMetres(MotionAsset& asset, const ImportOptions& options, GltfSource& source);

// The file's numbers for joint `joint` of a rig read through toMetres (unchanged when `source`
// holds no factors).
glm::dvec3 translationToFile(const GltfSource& source, int joint, const glm::dvec3& metres);
glm::dvec3 scaleToFile(const GltfSource& source, int joint, const glm::dvec3& scale);

// `clip` in the file's numbers, for writing on the original document's nodes.
// Precondition: clip.joint_count equals the size of source's factors (when it has any).
Clip clipToFile(const Clip& clip, const GltfSource& source);

}  // namespace sinew::motion::gltf

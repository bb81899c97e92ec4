# Imports files into Blender (headless) and checks each armature's bone count and frame range.
# Usage: blender -b --factory-startup --python-exit-code 1 --python blender_import.py --
#            FILE:BONES:FRAMES ...
# Debian's Blender 3.4 needs two workarounds: its BVH importer opens files with mode 'rU', which
# Python 3.11 rejects, and its glTF importer uses numpy.bool, removed in NumPy 1.24.
import builtins
import sys

_open = builtins.open


def _open_without_u(file, mode="r", *args, **kwargs):
    if isinstance(mode, str):
        mode = mode.replace("U", "")
    return _open(file, mode, *args, **kwargs)


builtins.open = _open_without_u

try:
    import numpy  # noqa: E402

    if not hasattr(numpy, "bool"):
        numpy.bool = bool
except ImportError:
    pass  # only the glTF importer needs numpy (Debian's python3-numpy)

import bpy  # noqa: E402

failures = []
for spec in sys.argv[sys.argv.index("--") + 1:]:
    path, bones, frames = spec.rsplit(":", 2)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if path.endswith(".bvh"):
        bpy.ops.import_anim.bvh(filepath=path, update_scene_fps=True, update_scene_duration=True)
    else:
        bpy.ops.import_scene.gltf(filepath=path)
    armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
    count = sum(len(a.data.bones) for a in armatures)
    actions = list(bpy.data.actions)
    keyed = 0
    if actions:
        start, end = actions[0].frame_range
        keyed = int(round(end - start)) + 1
    print(f"blender: {path}: {len(armatures)} armature(s), {count} bones, {keyed} frames keyed")
    if count != int(bones):
        failures.append(f"{path}: {count} bones, expected {bones}")
    if int(frames) > 0 and keyed != int(frames):
        failures.append(f"{path}: {keyed} frames keyed, expected {frames}")

if failures:
    raise SystemExit("blender import failed:\n  " + "\n  ".join(failures))
print(f"blender: all {len(sys.argv[sys.argv.index('--') + 1:])} files imported as expected")

"""Open a deepsea asset in Blender: the lamps' beams (the `density` preview grid) as a glowing
volume, a camera matching the rig's camera, small spheres at the lamps; optionally render a
preview PNG.

blender -b --factory-startup --python open_asset.py -- ASSET.vdb [--deepsea PATH]
        [--render OUT.png] [--samples N] [--resolution W] [--save OUT.blend] [--strength S]
        [--view beams|camera]

Works with any Blender build (no OpenVDB module needed in its Python). The asset's metadata
(camera, rig, frustum) comes from `deepsea info --json ASSET`, with the deepsea binary found as
--deepsea PATH, else $DEEPSEA, else next to this script's install location
(<prefix>/share/deepsea/blender/ -> <prefix>/bin/deepsea), else on PATH. Without one, the
`deepsea:bake` JSON is read from the file's own header (plain Python; no integrity check).
World frame of the asset's grids: OpenGL-style camera frame (x right, y up, looking down -z),
which is a Blender camera with identity rotation at the origin: in Blender (Z up) the rig looks
down -Z, the image's up along +Y.
"""
import argparse
import json
import os
import shutil
import struct
import subprocess
import sys

import bpy


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="open_asset.py")
    p.add_argument("asset")
    p.add_argument("--deepsea", help="the deepsea binary (default: $DEEPSEA, the install, PATH)")
    p.add_argument("--render")
    p.add_argument("--samples", type=int, default=8)
    p.add_argument("--resolution", type=int, default=480, help="render width in pixels")
    p.add_argument("--strength", type=float, default=8.0, help="emission strength of the beams")
    p.add_argument("--view", choices=["beams", "camera"], default="beams",
                   help="render the beams from beside the rig (16:9), or through the rig's camera")
    p.add_argument("--save")
    return p.parse_args(argv)


def find_deepsea(explicit):
    """The deepsea binary, or None."""
    if explicit:
        if not (os.path.isfile(explicit) and os.access(explicit, os.X_OK)):
            sys.exit(f"open_asset.py: --deepsea {explicit}: not an executable")
        return explicit
    here = os.path.dirname(os.path.realpath(__file__))
    candidates = [os.environ.get("DEEPSEA", ""),
                  os.path.join(here, "..", "..", "..", "bin", "deepsea")]  # installed layout
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return os.path.normpath(c)
    return shutil.which("deepsea")


def header_metadata(path):
    """The file-level metadata of an OpenVDB file (format 222 or later), read as OpenVDB
    writes it: magic, version, library version, grid-offset flag, 36-byte UUID, then a count
    and (name, type, value) entries, each length-prefixed. String values only."""
    with open(path, "rb") as f:
        data = f.read(1 << 20)

    def u32(at):
        return struct.unpack_from("<I", data, at)[0]

    if data[:4] != b" BDV":
        raise ValueError(f"{path}: not an OpenVDB file")
    if u32(8) < 222:
        raise ValueError(f"{path}: OpenVDB file format {u32(8)} is too old")

    def blob(at):  # a length-prefixed string or value, and the position after it
        n = u32(at)
        return data[at + 4:at + 4 + n], at + 4 + n

    pos = 8 + 4 + 8 + 1 + 36
    meta = {}
    count, pos = u32(pos), pos + 4
    for _ in range(count):
        name, pos = blob(pos)
        kind, pos = blob(pos)
        value, pos = blob(pos)
        if kind == b"string":
            meta[name.decode()] = value.decode()
    return meta


def asset_info(path, deepsea):
    """What `deepsea info --json` prints (keys "bake", "frustum_extent", "grids"), or the
    file's own `deepsea:bake` when there is no deepsea binary."""
    if deepsea:
        out = subprocess.run([deepsea, "info", "--json", path], capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"open_asset.py: {deepsea} info: {out.stderr.strip()}")
        return json.loads(out.stdout)
    print("open_asset.py: no deepsea binary (--deepsea, $DEEPSEA, PATH): reading the file's "
          "header", file=sys.stderr)
    bake = header_metadata(path).get("deepsea:bake")
    if bake is None:
        sys.exit(f"open_asset.py: {path}: no deepsea:bake metadata (not a deepsea asset)")
    return {"bake": json.loads(bake)}


def cone_box(meta):
    """Centre and size (metres) of the beams: the density grid's world bounds, or a guess
    (without deepsea info)."""
    for g in meta.get("grids", []):
        if g["name"] == "density":
            lo, hi = g["world_min"], g["world_max"]
            return [(a + b) / 2 for a, b in zip(lo, hi)], max(b - a for a, b in zip(lo, hi))
    return [0.0, 0.0, -1.0], 3.0


def main():
    args = parse_args()
    meta = asset_info(args.asset, find_deepsea(args.deepsea))
    info = meta["bake"]
    cam = info["camera"]
    scene = bpy.context.scene
    for obj in list(scene.objects):
        bpy.data.objects.remove(obj, do_unlink=True)

    volume = bpy.data.volumes.new("deepsea_asset")
    volume.filepath = args.asset
    obj = bpy.data.objects.new("deepsea_asset", volume)
    scene.collection.objects.link(obj)
    volume.grids.load()
    for g in volume.grids:
        print(f"grid {g.name} {g.data_type}")

    # The beams glow: density is the lamps' source in decades (docs/asset-format.md).
    mat = bpy.data.materials.new("deepsea_inscatter")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    vol = nodes.new("ShaderNodeVolumePrincipled")
    dens = nodes.new("ShaderNodeAttribute")
    dens.attribute_name = "density"
    # density^8: the bright cores of the beams stand out of their fainter spread
    power = nodes.new("ShaderNodeMath")
    power.operation = "POWER"
    power.inputs[1].default_value = 8.0
    links.new(dens.outputs["Fac"], power.inputs[0])
    scale = nodes.new("ShaderNodeMath")
    scale.operation = "MULTIPLY"
    scale.inputs[1].default_value = args.strength
    links.new(power.outputs[0], scale.inputs[0])
    links.new(scale.outputs[0], vol.inputs["Emission Strength"])
    vol.inputs["Emission Color"].default_value = (0.55, 0.75, 1.0, 1.0)
    vol.inputs["Density"].default_value = 0.0  # show the light, not an absorbing fog
    links.new(vol.outputs["Volume"], out.inputs["Volume"])
    volume.materials.append(mat)

    # Camera: pinhole with the asset's intrinsics.
    cam_data = bpy.data.cameras.new("deepsea_camera")
    cam_data.sensor_fit = "HORIZONTAL"
    cam_data.sensor_width = 36.0
    cam_data.lens = cam["fx"] / cam["width"] * 36.0
    cam_data.shift_x = ((cam["width"] - 1) / 2 - cam["cx"]) / cam["width"]
    cam_data.shift_y = (cam["cy"] - (cam["height"] - 1) / 2) / cam["width"]
    cam_data.clip_end = 1000.0
    cam_obj = bpy.data.objects.new("deepsea_camera", cam_data)
    scene.collection.objects.link(cam_obj)
    scene.camera = cam_obj
    if args.view == "beams":
        # A second camera beside the rig, across the plane of the beams (Blender's -Y) and a
        # little above and to the side, looking at the middle of the beams' box.
        side = bpy.data.objects.new("side_view", bpy.data.cameras.new("side_view"))
        side.data.lens = 30.0
        side.data.clip_end = 1000.0
        scene.collection.objects.link(side)
        centre, size = cone_box(meta)
        side.location = [c + d * size for c, d in zip(centre, (0.3, -1.0, 0.6))]
        target = bpy.data.objects.new("cones_centre", None)
        target.location = [centre[0], centre[1], centre[2] + 0.25 * size]  # nearer the lamps
        scene.collection.objects.link(target)
        track = side.constraints.new("TRACK_TO")
        track.target = target
        track.track_axis = "TRACK_NEGATIVE_Z"
        track.up_axis = "UP_Y"
        scene.camera = side

    for light in info["rig"]["lights"]:
        x, y, z = light["position"]
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.05, location=(x, -y, -z))
        bpy.context.object.name = "lamp_" + light.get("name", "")

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.use_denoising = False  # Debian builds Blender without OpenImageDenoise
    scene.cycles.volume_step_rate = 4.0
    scene.cycles.max_bounces = 0  # emission only: nothing to bounce
    scene.render.resolution_x = args.resolution
    aspect = cam["height"] / cam["width"] if args.view == "camera" else 9 / 16
    scene.render.resolution_y = max(1, round(args.resolution * aspect))
    scene.render.resolution_percentage = 100
    world = bpy.data.worlds.new("black")
    world.color = (0, 0, 0)
    scene.world = world
    if args.save:
        bpy.ops.wm.save_as_mainfile(filepath=args.save)
    if args.render:
        scene.render.filepath = args.render
        scene.render.image_settings.file_format = "PNG"
        bpy.ops.render.render(write_still=True)
        print(f"rendered {args.render}")


if __name__ == "__main__":
    main()

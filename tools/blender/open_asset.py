"""Open a deepsea asset in Blender: the in-scatter preview grids as a glowing volume, a camera
matching the rig's camera, small spheres at the lamps; optionally render a preview PNG.

blender -b --factory-startup --python tools/blender/open_asset.py -- ASSET.vdb
        [--render OUT.png] [--samples N] [--resolution W] [--save OUT.blend] [--strength S]

The asset's metadata (camera, rig) is read with Debian's /usr/bin/python3 and pyopenvdb,
because Blender's bundled Python has no OpenVDB bindings. World frame of the asset's grids:
OpenGL-style camera frame (x right, y up, looking down -z), which is a Blender camera with
identity rotation at the origin.
"""
import argparse
import json
import math
import subprocess
import sys

import bpy

READ_META = (
    "import json, sys, pyopenvdb as vdb\n"
    "m = vdb.readMetadata(sys.argv[1])\n"
    "print(m.get('deepsea:bake') or vdb.readAllGridMetadata(sys.argv[1])[0]['deepsea:bake'])\n"
)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="open_asset.py")
    p.add_argument("asset")
    p.add_argument("--render")
    p.add_argument("--samples", type=int, default=16)
    p.add_argument("--resolution", type=int, default=320, help="render width in pixels")
    p.add_argument("--strength", type=float, default=0.4, help="emission strength of the cones")
    p.add_argument("--view", choices=["camera", "side"], default="camera",
                   help="render through the rig's camera, or from beside the rig")
    p.add_argument("--save")
    return p.parse_args(argv)


def bake_info(path):
    out = subprocess.run(["/usr/bin/python3", "-c", READ_META, path], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def main():
    args = parse_args()
    info = bake_info(args.asset)
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

    # The preview grids glow with their own colour: density is the in-scatter luminance.
    mat = bpy.data.materials.new("deepsea_inscatter")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    vol = nodes.new("ShaderNodeVolumePrincipled")
    dens = nodes.new("ShaderNodeAttribute")
    dens.attribute_name = "density"
    col = nodes.new("ShaderNodeAttribute")
    col.attribute_name = "color"
    scale = nodes.new("ShaderNodeMath")
    scale.operation = "MULTIPLY"
    scale.inputs[1].default_value = args.strength
    links.new(dens.outputs["Fac"], scale.inputs[0])
    links.new(scale.outputs[0], vol.inputs["Emission Strength"])
    links.new(col.outputs["Color"], vol.inputs["Emission Color"])
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
    if args.view == "side":
        # A second camera above and beside the rig, looking at the cones in front of it.
        side = bpy.data.objects.new("side_view", bpy.data.cameras.new("side_view"))
        side.data.lens = 24.0
        side.data.clip_end = 1000.0
        scene.collection.objects.link(side)
        side.location = (5.0, 3.0, -1.0)
        target = bpy.data.objects.new("cones_centre", None)
        target.location = (0.0, 0.0, -3.0)
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
    scene.render.resolution_x = args.resolution
    scene.render.resolution_y = max(1, round(args.resolution * cam["height"] / cam["width"]))
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

"""Render a deepsea scene description with Blender Cycles: an independent ground truth.

usage: blender -b --factory-startup --python render_scene.py -- SCENE.json OUT.exr [SCENE2.json OUT2.exr ...]

Each pair is rendered from a fresh scene (one Blender start-up for several renders, e.g. seeds).
The set-up follows ../shared/CYCLES.md point by point; see docs/validation-cycles.md.

Scene JSON (deepsea's conventions: OpenCV camera frame, x right, y down, z forward, metres):
  camera: {width, height, fx, fy, cx, cy}      pixel (u, v) has its centre at (u, v)
  lights: [{position: [x,y,z], direction: [x,y,z], intensity: [R,G,B] (W/sr), sigma_deg}]
  water:  {c: [R,G,B], b: [R,G,B], g}          beam attenuation, scattering (1/m), HG g
  plane:  {point: [x,y,z], normal: [x,y,z], albedo: [R,G,B]}   optional, Lambertian, linear
  orders: "single" (volume_bounces = 0) | "all" (every bounce count 64)
  samples, seed
  water_half_size: optional, half the side of the water cube around the camera (default 20 m)
  plane_half_size: optional, half the side of the square plane (default 12 m)

Output: 32-bit multilayer EXR, channels ViewLayer.<pass>.<R|G|B> with the passes Combined,
VolumeDir, VolumeInd, DiffDir, DiffInd, DiffCol.
"""
import json
import math
import sys

import bpy
import mathutils


def to_blender(p):
    """deepsea / OpenCV camera frame -> Blender world: 180 degrees about x."""
    return mathutils.Vector((p[0], -p[1], -p[2]))


def clear_scene():
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.lights, bpy.data.cameras, bpy.data.materials):
        for block in list(coll):
            coll.remove(block)


def setup_render(scene, desc):
    cam = desc["camera"]
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x = int(cam["width"])
    r.resolution_y = int(cam["height"])
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    r.film_transparent = False
    r.use_compositing = False
    r.use_sequencer = False
    r.use_persistent_data = False

    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = int(desc["samples"])
    cy.seed = int(desc["seed"])
    cy.use_animated_seed = False
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 0.01
    cy.use_layer_samples = "IGNORE"
    cy.sample_offset = 0
    orders = desc.get("orders", "single")
    if orders == "single":
        n = 0
    elif orders == "all":
        n = 64
    else:
        raise ValueError(f"orders must be 'single' or 'all', not {orders!r}")
    for attr in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                 "volume_bounces", "transparent_max_bounces"):
        setattr(cy, attr, n)
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.blur_glossy = 0.0

    vs = scene.view_settings
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0

    layer = scene.view_layers[0]
    layer.use_pass_combined = True
    layer.use_pass_z = False
    layer.use_pass_diffuse_direct = True
    layer.use_pass_diffuse_indirect = True
    layer.use_pass_diffuse_color = True
    layer.cycles.use_pass_volume_direct = True
    layer.cycles.use_pass_volume_indirect = True

    img = r.image_settings
    img.file_format = "OPEN_EXR_MULTILAYER"
    img.color_depth = "32"
    img.exr_codec = "ZIP"


def setup_camera(scene, cam):
    """Camera at the origin, identity rotation (looks down -Z, +Y up = deepsea's +z, -y).

    Cycles pixel u covers [u, u+1] with the optical centre at W/2, so deepsea's principal point
    (pixel centres at integers) is cx = W/2 - 0.5 when the shift is 0; other principal points
    become a lens shift, in units of the sensor width (sensor fit horizontal)."""
    w, h = int(cam["width"]), int(cam["height"])
    fx, fy = float(cam["fx"]), float(cam["fy"])
    if abs(fx - fy) > 1e-9 * fx:
        raise ValueError("Cycles needs square pixels: fx == fy")
    data = bpy.data.cameras.new("deepsea_camera")
    data.type = "PERSP"
    data.sensor_fit = "HORIZONTAL"
    data.sensor_width = 36.0
    data.lens_unit = "MILLIMETERS"
    data.lens = fx * 36.0 / w
    data.shift_x = (w / 2 - 0.5 - float(cam["cx"])) / w
    data.shift_y = (float(cam["cy"]) - (h / 2 - 0.5)) / w
    data.clip_start = 1e-5  # CYCLES.md: the default 0.1 m cuts the brightest water away
    data.clip_end = 1e5
    obj = bpy.data.objects.new("deepsea_camera", data)
    obj.matrix_world = mathutils.Matrix.Identity(4)
    scene.collection.objects.link(obj)
    scene.camera = obj


def gaussian_light_nodes(light, axis_world, sigma_deg):
    """Emission strength exp(-acos(N . a)^2 / (2 sigma^2)); for a radius-0 point light
    Geometry > Normal is the unit vector from the light to the shaded point (world space)."""
    light.use_nodes = True
    nt = light.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputLight")
    emit = nt.nodes.new("ShaderNodeEmission")
    emit.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    geo = nt.nodes.new("ShaderNodeNewGeometry")
    dot = nt.nodes.new("ShaderNodeVectorMath")
    dot.operation = "DOT_PRODUCT"
    dot.inputs[1].default_value = tuple(axis_world)
    clamp = nt.nodes.new("ShaderNodeClamp")
    clamp.inputs["Min"].default_value = -1.0
    clamp.inputs["Max"].default_value = 1.0
    acos = nt.nodes.new("ShaderNodeMath")
    acos.operation = "ARCCOSINE"
    sq = nt.nodes.new("ShaderNodeMath")
    sq.operation = "MULTIPLY"
    scale = nt.nodes.new("ShaderNodeMath")
    scale.operation = "MULTIPLY"
    sigma = math.radians(float(sigma_deg))
    scale.inputs[1].default_value = -1.0 / (2.0 * sigma * sigma)
    exp = nt.nodes.new("ShaderNodeMath")
    exp.operation = "POWER"
    exp.inputs[0].default_value = math.e
    link = nt.links.new
    link(geo.outputs["Normal"], dot.inputs[0])
    link(dot.outputs["Value"], clamp.inputs["Value"])
    link(clamp.outputs["Result"], acos.inputs[0])
    link(acos.outputs["Value"], sq.inputs[0])
    link(acos.outputs["Value"], sq.inputs[1])
    link(sq.outputs["Value"], scale.inputs[0])
    link(scale.outputs["Value"], exp.inputs[1])
    link(exp.outputs["Value"], emit.inputs["Strength"])
    link(emit.outputs["Emission"], out.inputs["Surface"])


def add_lights(scene, lights):
    for i, l in enumerate(lights):
        inten = [float(x) for x in l["intensity"]]
        peak = max(inten)
        if peak <= 0:
            continue
        data = bpy.data.lights.new(f"lamp{i}", type="POINT")
        # radius 0: radiant intensity = Power * color / (4 pi) W/sr (CYCLES.md)
        data.shadow_soft_size = 0.0
        data.energy = 4.0 * math.pi * peak
        data.color = tuple(x / peak for x in inten)
        data.cycles.cast_shadow = True
        data.cycles.use_multiple_importance_sampling = True
        data.cycles.max_bounces = 1024
        axis = to_blender(l["direction"]).normalized()
        gaussian_light_nodes(data, axis, l["sigma_deg"])
        obj = bpy.data.objects.new(f"lamp{i}", data)
        obj.location = to_blender(l["position"])
        scene.collection.objects.link(obj)


def add_water(scene, water, half):
    c = [float(x) for x in water["c"]]
    b = [float(x) for x in water["b"]]
    if any(bi > ci or bi < 0 for bi, ci in zip(b, c)):
        raise ValueError("water needs 0 <= b <= c")
    dens = max(c)
    # sigma_s = D Cs = b, sigma_a = D (1 - Ca) = c - b (CYCLES.md)
    cs = [bi / dens for bi in b]
    ca = [1.0 - (ci - bi) / dens for ci, bi in zip(c, b)]
    mat = bpy.data.materials.new("water")
    mat.use_nodes = True
    mat.cycles.homogeneous_volume = True
    mat.cycles.volume_sampling = "MULTIPLE_IMPORTANCE"
    mat.cycles.volume_interpolation = "LINEAR"
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    sca = nt.nodes.new("ShaderNodeVolumeScatter")
    sca.inputs["Color"].default_value = (*cs, 1.0)
    sca.inputs["Density"].default_value = dens
    sca.inputs["Anisotropy"].default_value = float(water["g"])
    ab = nt.nodes.new("ShaderNodeVolumeAbsorption")
    ab.inputs["Color"].default_value = (*ca, 1.0)
    ab.inputs["Density"].default_value = dens
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(sca.outputs["Volume"], add.inputs[0])
    nt.links.new(ab.outputs["Volume"], add.inputs[1])
    nt.links.new(add.outputs["Shader"], out.inputs["Volume"])

    h = float(half)
    verts = [(x, y, z) for x in (-h, h) for y in (-h, h) for z in (-h, h)]
    # outward-facing quads (counter-clockwise seen from outside)
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    mesh = bpy.data.meshes.new("water")
    mesh.from_pydata(verts, [], faces)
    mesh.validate()
    mesh.materials.append(mat)
    obj = bpy.data.objects.new("water", mesh)
    scene.collection.objects.link(obj)


def add_plane(scene, plane, half):
    n = to_blender(plane["normal"]).normalized()
    p0 = to_blender(plane["point"])
    # orthonormal basis (e1, e2, n), right-handed so that the quad's normal is n
    helper = mathutils.Vector((1.0, 0.0, 0.0)) if abs(n.x) < 0.9 else mathutils.Vector((0.0, 1.0, 0.0))
    e1 = n.cross(helper).normalized()
    e2 = n.cross(e1)
    h = float(half)
    verts = [tuple(p0 + h * (s * e1 + t * e2)) for s, t in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    if (mathutils.Vector(verts[1]) - mathutils.Vector(verts[0])).cross(
            mathutils.Vector(verts[2]) - mathutils.Vector(verts[1])).dot(n) < 0:
        verts.reverse()
    mesh = bpy.data.meshes.new("plane")
    mesh.from_pydata(verts, [], [(0, 1, 2, 3)])
    mesh.validate()
    mat = bpy.data.materials.new("plane")
    mat.use_nodes = True
    nt = mat.node_tree
    for node in list(nt.nodes):
        nt.nodes.remove(node)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    diff = nt.nodes.new("ShaderNodeBsdfDiffuse")  # roughness 0: albedo / pi
    diff.inputs["Color"].default_value = (*[float(x) for x in plane["albedo"]], 1.0)
    diff.inputs["Roughness"].default_value = 0.0
    nt.links.new(diff.outputs["BSDF"], out.inputs["Surface"])
    mesh.materials.append(mat)
    obj = bpy.data.objects.new("plane", mesh)
    scene.collection.objects.link(obj)


def black_world(scene):
    world = scene.world or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    for node in world.node_tree.nodes:
        if node.type == "BACKGROUND":
            node.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
            node.inputs["Strength"].default_value = 0.0
    world.cycles.sampling_method = "NONE"


def render(desc, out_path):
    clear_scene()
    scene = bpy.context.scene
    setup_render(scene, desc)
    setup_camera(scene, desc["camera"])
    black_world(scene)
    add_lights(scene, desc["lights"])
    add_water(scene, desc["water"], desc.get("water_half_size", 20.0))
    if desc.get("plane"):
        add_plane(scene, desc["plane"], desc.get("plane_half_size", 12.0))
    scene.render.filepath = out_path
    scene.render.use_file_extension = False
    bpy.ops.render.render(write_still=True)
    print(f"render_scene: wrote {out_path}", flush=True)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not argv or len(argv) % 2:
        print(__doc__)
        sys.exit(2)
    for scene_path, out_path in zip(argv[0::2], argv[1::2]):
        with open(scene_path) as f:
            render(json.load(f), out_path)


main()

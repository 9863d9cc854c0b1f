"""Renders one scene with Blender's Cycles for the comparison scripts; runs inside Blender:

    blender -b --factory-startup -noaudio --python-exit-code 1 --python scripts/blender_render.py -- JOB.json

scripts/blender_common.py writes JOB.json and reads what this script writes; nothing else should
call it. The job (every coordinate in Penumbra's y-up world, every angle in degrees):

    scene        OBJ or glTF/GLB file, read with Blender's own importer (OBJ: -z forward, y up;
                 glTF: Khronos' importer onto the Principled BSDF); both map y-up (x, y, z) to
                 Blender's z-up (x, -z, y)
    materials    "native" (the importer's) or {name: {"kd": rgb, "ke": rgb, "map_kd": file|null}}:
                 Lambert (a Diffuse BSDF of roughness 0, kd times the sRGB texture) plus emission
                 from the front side only, as Penumbra emits; faces without a listed material get
                 Diffuse kd 0.8 (Penumbra's default material)
    camera       {"eye", "look_at", "up", "fov" (vertical)} or "scene" (the model's first perspective
                 camera, else "frame") or {"frame": {"azimuth", "elevation", "fov"}}: look at the
                 centre of the bounding box from that direction (azimuth from +z towards +x,
                 elevation above the horizon), far enough for its bounding sphere to fit the frame
    environment  null (black), {"rgb": [r, g, b]} or {"file": lat-long image, "rotate": degrees},
                 mapped as Penumbra maps --env FILE / --env-rotate (docs/rendering.md), texels
                 looked up nearest-neighbour
    width, height, spp, max_bounces, seed, threads (0: all cores)
    output       PFM file (linear radiance, float); "probe": true imports and places the camera
                 but renders nothing
    report       JSON file: render_seconds (the wall time of bpy.ops.render.render: Blender's scene
                 export to Cycles, image loading, BVH build, light and importance-map build and all
                 samples; not Blender's start, the import or the image writing), import_seconds,
                 the camera as Penumbra options, the scene's bounds, Blender's version

Cycles is set to match Penumbra's path tracer: CPU, box pixel filter one pixel wide, no denoising, no
adaptive sampling, no clamping, no path guiding, no light tree (when the version has one), caustics
on, every bounce limit max_bounces (Penumbra's --max-depth D is max_bounces D - 1), the Standard view
transform (the PFM is written from the linear EXR anyway).
"""
import json
import math
import os
import sys
import tempfile
import time

import bpy
import numpy as np
from mathutils import Matrix, Vector


def to_blender(v):
    """Penumbra's y-up (x, y, z) as Blender's z-up (x, -z, y): what both importers do."""
    return Vector((v[0], -v[2], v[1]))


def from_blender(v):
    return [v[0], v[2], -v[1]]


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for collection in (bpy.data.meshes, bpy.data.materials, bpy.data.cameras, bpy.data.lights,
                       bpy.data.images, bpy.data.worlds):
        for block in list(collection):
            collection.remove(block)


def import_scene(path):
    ext = os.path.splitext(path)[1].lower()
    if ext == ".obj":
        bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
    elif ext in (".gltf", ".glb"):
        # Khronos' importer in Blender 3.4 still says np.bool, which numpy 1.24 (Debian 12's) removed;
        # it was an alias of the builtin bool (fixed in the importer of Blender 3.5).
        if "bool" not in np.__dict__:
            np.bool = bool
        bpy.ops.import_scene.gltf(filepath=path)
    else:
        raise SystemExit(f"blender_render.py: {path}: only OBJ and glTF are compared")


def smooth_like_penumbra(obj):
    """Penumbra smooths meshes without normals across edges under 30 degrees; Blender's auto smooth
    splits the same edges (both weigh face normals by corner angle)."""
    mesh = obj.data
    if mesh.has_custom_normals:
        return
    for poly in mesh.polygons:
        poly.use_smooth = True
    mesh.use_auto_smooth = True
    mesh.auto_smooth_angle = math.radians(30.0)


def image_node(nodes, kind, path, colorspace, interpolation):
    node = nodes.new(kind)
    node.image = bpy.data.images.load(path, check_existing=True)
    node.image.colorspace_settings.name = colorspace
    node.interpolation = interpolation
    return node


def lambert_material(name, spec):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Roughness"].default_value = 0.0
    kd = list(spec.get("kd", [0.8, 0.8, 0.8]))
    diffuse.inputs["Color"].default_value = (*kd, 1.0)
    if spec.get("map_kd"):
        tex = image_node(nodes, "ShaderNodeTexImage", spec["map_kd"], "sRGB", "Linear")
        tex.extension = "REPEAT"
        mult = nodes.new("ShaderNodeMixRGB")
        mult.blend_type = "MULTIPLY"
        mult.inputs["Fac"].default_value = 1.0
        mult.inputs["Color1"].default_value = (*kd, 1.0)
        links.new(tex.outputs["Color"], mult.inputs["Color2"])
        links.new(mult.outputs["Color"], diffuse.inputs["Color"])
    shader = diffuse.outputs["BSDF"]
    ke = spec.get("ke") or [0.0, 0.0, 0.0]
    if max(ke) > 0.0:
        emission = nodes.new("ShaderNodeEmission")
        emission.inputs["Color"].default_value = (*ke, 1.0)
        # Front side only (Penumbra's emitters are one-sided): strength 1 - backfacing.
        geometry = nodes.new("ShaderNodeNewGeometry")
        front = nodes.new("ShaderNodeMath")
        front.operation = "SUBTRACT"
        front.inputs[0].default_value = 1.0
        links.new(geometry.outputs["Backfacing"], front.inputs[1])
        links.new(front.outputs["Value"], emission.inputs["Strength"])
        add = nodes.new("ShaderNodeAddShader")
        links.new(shader, add.inputs[0])
        links.new(emission.outputs["Emission"], add.inputs[1])
        shader = add.outputs["Shader"]
    links.new(shader, out.inputs["Surface"])
    return mat


def apply_lambert(meshes, table):
    """Replaces every imported material by its Lambert version from the table, by name (Blender's
    importer may append .001 to a name it has seen); returns the names it did not find."""
    made, unknown = {}, set()

    def resolve(name):
        if name is None or name in table:
            return name
        base = name.rsplit(".", 1)[0]
        if base in table:
            return base
        unknown.add(name)
        return None

    def material(key):
        if key not in made:
            made[key] = lambert_material(f"lambert:{key}", table[key] if key else {})
        return made[key]

    for obj in meshes:
        if not obj.material_slots:
            obj.data.materials.append(material(None))
        for slot in obj.material_slots:
            slot.material = material(resolve(slot.material.name if slot.material else None))
    return sorted(unknown)


def setup_world(scene, env):
    world = bpy.data.worlds.new("environment")
    scene.world = world
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = nodes["Background"]
    if env is None:
        background.inputs["Color"].default_value = (0, 0, 0, 1)
        background.inputs["Strength"].default_value = 0.0
    elif "rgb" in env:
        background.inputs["Color"].default_value = (*env["rgb"], 1)
        background.inputs["Strength"].default_value = 1.0
    else:
        tex = image_node(nodes, "ShaderNodeTexEnvironment", env["file"], "Linear", "Closest")
        tex.projection = "EQUIRECTANGULAR"
        coords = nodes.new("ShaderNodeTexCoord")
        mapping = nodes.new("ShaderNodeMapping")
        mapping.vector_type = "POINT"
        # Blender's u = 1/2 lies along +x, Penumbra's along -z (Blender's +y): turn the lookup
        # direction by -90 degrees about z, and by -rotate for the environment's own turn.
        mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(-90.0 - env.get("rotate", 0.0)))
        links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
        links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
        links.new(tex.outputs["Color"], background.inputs["Color"])
        background.inputs["Strength"].default_value = 1.0


def bounds(meshes):
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for obj in meshes:
        for corner in obj.bound_box:
            p = from_blender(obj.matrix_world @ Vector(corner))
            lo = [min(a, b) for a, b in zip(lo, p)]
            hi = [max(a, b) for a, b in zip(hi, p)]
    return lo, hi


def frame_camera(lo, hi, frame, aspect):
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    radius = max(1e-6, 0.5 * math.dist(lo, hi))
    az, el = math.radians(frame["azimuth"]), math.radians(frame["elevation"])
    direction = [math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)]
    half_v = math.radians(frame["fov"]) / 2
    half_h = math.atan(math.tan(half_v) * aspect)
    distance = radius / math.sin(min(half_v, half_h))
    eye = [c + distance * d for c, d in zip(centre, direction)]
    return {"eye": eye, "look_at": centre, "up": [0.0, 1.0, 0.0], "fov": frame["fov"]}


def scene_camera(scene):
    """The model's camera as Penumbra options, or None when it has no perspective camera."""
    cams = [o for o in scene.objects if o.type == "CAMERA" and o.data.type == "PERSP"]
    if scene.camera in cams:
        cams.remove(scene.camera)
        cams.insert(0, scene.camera)
    if not cams:
        return None
    cam = cams[0]
    frame = cam.data.view_frame(scene=scene)  # corners in camera space, z < 0
    half_v = math.atan(max(abs(c.y) for c in frame) / abs(frame[0].z))
    m = cam.matrix_world
    eye = m.translation
    forward = (m.to_3x3() @ Vector((0, 0, -1))).normalized()
    up = (m.to_3x3() @ Vector((0, 1, 0))).normalized()
    return {"eye": from_blender(eye), "look_at": from_blender(eye + forward), "up": from_blender(up),
            "fov": math.degrees(2 * half_v), "name": cam.name}


def place_camera(scene, cam_spec):
    for obj in [o for o in scene.objects if o.type == "CAMERA"]:
        bpy.data.objects.remove(obj, do_unlink=True)
    data = bpy.data.cameras.new("penumbra_camera")
    obj = bpy.data.objects.new("penumbra_camera", data)
    scene.collection.objects.link(obj)
    scene.camera = obj
    data.type = "PERSP"
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(cam_spec["fov"])
    eye, target, up = (to_blender(cam_spec[k]) for k in ("eye", "look_at", "up"))
    forward = (target - eye).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    obj.matrix_world = Matrix(((right.x, true_up.x, -forward.x, eye.x),
                               (right.y, true_up.y, -forward.y, eye.y),
                               (right.z, true_up.z, -forward.z, eye.z),
                               (0, 0, 0, 1)))
    distance = (target - eye).length
    data.clip_start = max(1e-6, 1e-5 * distance)
    data.clip_end = 1e8


def configure_cycles(scene, job):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = job["spp"]
    c.seed = job["seed"]
    c.use_animated_seed = False
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = job["max_bounces"]
    c.volume_bounces = 0
    c.film_exposure = 1.0
    for name, value in (("use_guiding", False), ("use_light_tree", False)):
        if hasattr(c, name):
            setattr(c, name, value)
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = job["width"], job["height"], 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = False
    r.use_persistent_data = False
    r.threads_mode = "FIXED" if job["threads"] > 0 else "AUTO"
    if job["threads"] > 0:
        r.threads = job["threads"]
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    settings = r.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_mode = "RGB"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"


def write_pfm(path, rgb, width, height):
    """PFM rows run bottom to top, as Blender's pixel buffers do."""
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(f"PF\n{width} {height}\n-1.0\n".encode())
        f.write(np.ascontiguousarray(rgb, dtype="<f4").tobytes())
    os.replace(tmp, path)


def save_render(scene, path, width, height):
    with tempfile.TemporaryDirectory(prefix="blender_render.") as tmp:
        exr = os.path.join(tmp, "render.exr")
        bpy.data.images["Render Result"].save_render(filepath=exr, scene=scene)
        image = bpy.data.images.load(exr)
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        write_pfm(path, pixels.reshape(height, width, 4)[:, :, :3], width, height)


def main():
    job = json.load(open(sys.argv[sys.argv.index("--") + 1]))
    scene = bpy.context.scene
    clear_scene()
    start = time.perf_counter()
    import_scene(job["scene"])
    import_seconds = time.perf_counter() - start
    bpy.context.view_layer.update()  # world matrices of the imported hierarchy
    meshes = [o for o in scene.objects if o.type == "MESH"]
    report = {"blender": bpy.app.version_string, "import_seconds": import_seconds, "meshes": len(meshes)}
    if job["materials"] != "native":
        for obj in meshes:
            smooth_like_penumbra(obj)
        report["unknown_materials"] = apply_lambert(meshes, job["materials"])
    lo, hi = bounds(meshes)
    report["bounds"] = [lo, hi]
    configure_cycles(scene, job)  # first: the image's aspect sets a model camera's vertical field of view
    cam = job["camera"]
    if cam == "scene":
        cam = scene_camera(scene)
        report["camera_source"] = f"the model's camera {cam['name']}" if cam else "framed (the model has none)"
        cam = cam or {"frame": job.get("frame", {"azimuth": 30.0, "elevation": 20.0, "fov": 40.0})}
    if "frame" in cam:
        cam = frame_camera(lo, hi, cam["frame"], job["width"] / job["height"])
    cam = {k: cam[k] for k in ("eye", "look_at", "up", "fov")}
    report["camera"] = cam
    place_camera(scene, cam)
    setup_world(scene, job.get("environment"))
    if not job.get("probe"):
        start = time.perf_counter()
        bpy.ops.render.render()
        report["render_seconds"] = time.perf_counter() - start
        save_render(scene, job["output"], job["width"], job["height"])
    with open(job["report"], "w") as f:
        json.dump(report, f, indent=1)


main()

# Builds a Blender Cycles scene from grapebench's scene.json (format "grapebench-cycles-1",
# written by sensors/render/cycles_render.cpp) and renders it headless:
#
#   blender -b --factory-startup -noaudio -P sensors/render/cycles_scene.py -- <work>/scene.json
#
# Writes into the folder of scene.json:
#   colour.f32  little-endian float32, H x W x 3, top row first: the linear Combined pass (radiance)
#   index.i32   little-endian int32, H x W, top row first: the object index pass (0: world / id 0)
# Exit status 0 on success; on any error one line "cycles_scene: <reason>" on stderr and exit 2.
#
# One UV-sphere mesh serves every berry and one capped unit cylinder every cylinder (linked
# duplicates, scaled and placed per object); per-object colours reach the shared materials
# through object custom properties read by Attribute nodes of type OBJECT. The passes come
# back through the compositor (File Output node, 32-bit float OpenEXR in a temporary
# folder, deleted afterwards).
# Blender's bundled Python and numpy only (Debian 12's `blender` 3.4).

import json
import math
import os
import shutil
import sys
import tempfile

FORMAT = "grapebench-cycles-1"
SPHERE_SEGMENTS = 48   # around the berry
SPHERE_RINGS = 24      # pole to pole
CYLINDER_SIDES = 32
# Light path bounces (the scene's `bounces`, default 12): every kind gets the same cap
# (Cycles' own defaults stop diffuse paths at 4, which cuts light through leaf layers
# and berries, where each translucent pass counts as a diffuse bounce). Russian roulette
# keeps long paths cheap.


class SceneError(Exception):
    pass


def fail(reason):
    sys.stdout.flush()
    sys.stderr.write("cycles_scene: " + " ".join(str(reason).split()) + "\n")
    sys.stderr.flush()
    sys.exit(2)


# ---------------------------------------------------------------------------------------
# scene.json reading: every key checked, a missing one named by its path.

def _key(d, key, path):
    if not isinstance(d, dict):
        raise SceneError("%s is not an object" % (path or "scene.json"))
    if key not in d:
        raise SceneError("missing key '%s'" % (path + "." + key if path else key))
    return d[key]


def _name(path, key):
    return path + "." + key if path else key


def _is_num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def num(d, key, path, lo=None, hi=None):
    v = _key(d, key, path)
    if not _is_num(v):
        raise SceneError("'%s' is not a finite number" % _name(path, key))
    v = float(v)
    if (lo is not None and v < lo) or (hi is not None and v > hi):
        raise SceneError("'%s' = %g is outside [%s, %s]" % (_name(path, key), v, lo, hi))
    return v


def integer(d, key, path, lo=None, hi=None):
    v = _key(d, key, path)
    if isinstance(v, float) and v.is_integer():
        v = int(v)
    if not isinstance(v, int) or isinstance(v, bool):
        raise SceneError("'%s' is not an integer" % _name(path, key))
    if (lo is not None and v < lo) or (hi is not None and v > hi):
        raise SceneError("'%s' = %d is outside [%s, %s]" % (_name(path, key), v, lo, hi))
    return v


def vec(d, key, path, n=3, lo=None, hi=None):
    v = _key(d, key, path)
    if not isinstance(v, list) or len(v) != n or not all(_is_num(x) for x in v):
        raise SceneError("'%s' is not a list of %d finite numbers" % (_name(path, key), n))
    v = [float(x) for x in v]
    if any((lo is not None and x < lo) or (hi is not None and x > hi) for x in v):
        raise SceneError("'%s' has a value outside [%s, %s]" % (_name(path, key), lo, hi))
    return v


def colour(d, key, path):
    return vec(d, key, path, 3, 0.0, None)


def string(d, key, path):
    v = _key(d, key, path)
    if not isinstance(v, str) or not v:
        raise SceneError("'%s' is not a non-empty string" % _name(path, key))
    return v


def array(d, key, path):
    v = _key(d, key, path)
    if not isinstance(v, list):
        raise SceneError("'%s' is not a list" % _name(path, key))
    return v


MAX_ID = 32767  # Blender's Object.pass_index is a short


def parse(doc, folder):
    s = {}
    fmt = _key(doc, "format", "")
    if fmt != FORMAT:
        raise SceneError("format is %r, want %r" % (fmt, FORMAT))
    im = _key(doc, "image", "")
    s["W"] = integer(im, "width", "image", 1, 65536)
    s["H"] = integer(im, "height", "image", 1, 65536)
    s["samples"] = integer(im, "samples", "image", 1, 1 << 24)
    s["bounces"] = integer(im, "bounces", "image", 1, 1024)
    s["diffuse"] = string(im, "diffuse", "image")
    if s["diffuse"] not in ("principled", "lambert"):
        raise SceneError("'image.diffuse' is %r, want principled or lambert" % s["diffuse"])
    s["seed"] = integer(im, "seed", "image") % 2147483648  # Cycles' seed is a non-negative int
    s["threads"] = integer(im, "threads", "image", 1, 1024)

    cam = _key(doc, "camera", "")
    s["pose"] = vec(cam, "pose", "camera", 16)
    s["fx"] = num(cam, "fx", "camera", 1e-9)
    s["fy"] = num(cam, "fy", "camera", 1e-9)
    s["cx"] = num(cam, "cx", "camera")
    s["cy"] = num(cam, "cy", "camera")
    s["sensor_width_mm"] = num(cam, "sensor_width_mm", "camera", 1e-9)
    s["f_number"] = num(cam, "f_number", "camera", 0.0)
    if s["f_number"] > 0:
        s["focus_distance"] = num(cam, "focus_distance", "camera", 1e-9)
    if abs(s["fx"] - s["fy"]) > 1e-6 * s["fx"]:
        raise SceneError("camera.fy (%g) differs from camera.fx (%g): Blender's pixels are square" % (s["fy"], s["fx"]))

    sun = _key(doc, "sun", "")
    d = vec(sun, "direction", "sun")
    n = math.sqrt(sum(x * x for x in d))
    if n < 1e-9:
        raise SceneError("'sun.direction' is the zero vector")
    s["sun_direction"] = [x / n for x in d]
    s["sun_irradiance"] = num(sun, "irradiance", "sun", 0.0)
    s["sun_colour"] = colour(sun, "colour", "sun")
    s["sun_angle_deg"] = num(sun, "angle_deg", "sun", 0.0, 180.0)

    sky = _key(doc, "sky", "")
    s["sky_kind"] = string(sky, "kind", "sky")
    if s["sky_kind"] not in ("clear", "overcast"):
        raise SceneError("'sky.kind' is %r, want 'clear' or 'overcast'" % s["sky_kind"])
    s["sky_scale"] = num(sky, "scale", "sky", 0.0)
    if s["sky_kind"] == "clear":
        s["sky_zenith"] = colour(sky, "zenith", "sky")
        s["sky_horizon"] = colour(sky, "horizon", "sky")

    g = _key(doc, "ground", "")
    s["ground_z"] = num(g, "z", "ground")
    s["ground_reflectance"] = colour(g, "reflectance", "ground")
    s["ground_half_size"] = num(g, "half_size", "ground", 0.0)

    berries = []
    for i, b in enumerate(array(doc, "berries", "")):
        p = "berries[%d]" % i
        berries.append({"centre": vec(b, "centre", p), "radius": num(b, "radius", p, 0.0),
                        "albedo": colour(b, "albedo", p), "transmittance": colour(b, "transmittance", p),
                        "id": integer(b, "id", p, 1, MAX_ID)})
    s["berries"] = berries
    if berries:
        bm = _key(doc, "berry_material", "")
        s["berry_f0"] = num(bm, "f0", "berry_material", 0.0, 1.0)
        s["berry_alpha"] = num(bm, "alpha", "berry_material", 0.0, 1.0)

    # The wood texture's atlas (sensors/render/wood_atlas.h): optional; with it, each drawn
    # cylinder names its frame and its rectangle.
    if "wood" in doc:
        wd = _key(doc, "wood", "")
        s["wood_png"] = os.path.join(folder, string(wd, "png", "wood"))
        if not os.path.isfile(s["wood_png"]):
            raise SceneError("wood.png: no file %s" % s["wood_png"])
        s["wood_width"] = integer(wd, "width", "wood", 1, 1 << 16)
        s["wood_height"] = integer(wd, "height", "wood", 1, 1 << 16)
        s["wood_amplitude"] = num(wd, "amplitude", "wood", 0.0, 1.0)
    cylinders = []
    for i, c in enumerate(array(doc, "cylinders", "")):
        p = "cylinders[%d]" % i
        cy = {"start": vec(c, "start", p), "end": vec(c, "end", p), "radius": num(c, "radius", p, 0.0),
              "albedo": colour(c, "albedo", p), "id": integer(c, "id", p, 0, MAX_ID)}
        if "wood_png" in s and cy["radius"] > 0 and cy["start"] != cy["end"]:
            cy["x_axis"] = vec(c, "x_axis", p, 3, -1.0, 1.0)
            axis = [e - b for b, e in zip(cy["start"], cy["end"])]
            length = math.sqrt(sum(v * v for v in axis))
            if abs(math.sqrt(sum(v * v for v in cy["x_axis"])) - 1) > 1e-6 or \
                    abs(sum(u * v for u, v in zip(cy["x_axis"], axis))) > 1e-6 * length:
                raise SceneError("'%s.x_axis' is not a unit vector normal to the cylinder's axis" % p)
            cy["atlas_origin"] = vec(c, "atlas_origin", p, 3, 0.0, float(max(s["wood_width"], s["wood_height"])))
            cy["atlas_steps"] = vec(c, "atlas_steps", p, 3, 0.0, float(max(s["wood_width"], s["wood_height"])))
        cylinders.append(cy)
    s["cylinders"] = cylinders

    leaves = []
    for i, lf in enumerate(array(doc, "leaves", "")):
        p = "leaves[%d]" % i
        verts = array(lf, "vertices", p)
        uv = array(lf, "uv", p)
        tris = array(lf, "triangles", p)
        leaf_id = integer(lf, "id", p, 0, MAX_ID)
        if len(uv) != len(verts):
            raise SceneError("'%s.uv' has %d entries for %d vertices" % (p, len(uv), len(verts)))
        leaves.append({"vertices": verts, "uv": uv, "triangles": tris, "id": leaf_id, "path": p})
    s["leaves"] = leaves
    if leaves:
        lm = _key(doc, "leaf_material", "")
        for key in ("albedo_png", "transmittance_png"):
            f = os.path.join(folder, string(lm, key, "leaf_material"))
            if not os.path.isfile(f):
                raise SceneError("leaf_material.%s: no file %s" % (key, f))
            s["leaf_" + key] = f
        s["leaf_back"] = num(lm, "back", "leaf_material", 0.0)
        s["leaf_f0"] = num(lm, "f0", "leaf_material", 0.0, 1.0)
        s["leaf_alpha"] = num(lm, "alpha", "leaf_material", 0.0, 1.0)

    out = _key(doc, "outputs", "")
    s["out_colour"] = os.path.join(folder, string(out, "colour", "outputs"))
    s["out_index"] = os.path.join(folder, string(out, "index", "outputs"))
    return s


# ---------------------------------------------------------------------------------------
# The Blender side.

def build_and_render(s, folder):
    import bpy
    import numpy as np
    from mathutils import Matrix, Vector

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    view_layer = scene.view_layers[0]
    W, H = s["W"], s["H"]

    # --- render settings
    r = scene.render
    r.engine = "CYCLES"
    if not hasattr(scene, "cycles"):
        raise SceneError("Blender has no Cycles (the cycles add-on is not enabled)")
    r.resolution_x, r.resolution_y, r.resolution_percentage = W, H, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    r.threads_mode = "FIXED"
    r.threads = s["threads"]
    r.film_transparent = False
    r.use_motion_blur = False
    r.use_compositing = True
    r.use_sequencer = False
    r.dither_intensity = 0.0
    r.use_persistent_data = False
    c = scene.cycles
    c.device = "CPU"
    c.samples = s["samples"]
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = s["seed"]
    c.use_animated_seed = False
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.film_exposure = 1.0
    c.time_limit = 0.0
    # No biasing shortcuts: Cycles' default clamps indirect samples at 10 and blurs glossy paths.
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.max_bounces = s["bounces"]
    c.diffuse_bounces = s["bounces"]
    c.glossy_bounces = s["bounces"]
    c.transmission_bounces = s["bounces"]
    c.transparent_max_bounces = s["bounces"]
    c.volume_bounces = 0
    c.caustics_reflective = True
    c.caustics_refractive = True
    vs = scene.view_settings
    scene.display_settings.display_device = "sRGB"
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    vs.use_curve_mapping = False
    scene.frame_start = scene.frame_end = 1
    scene.frame_set(1)
    view_layer.use_pass_combined = True
    view_layer.use_pass_object_index = True

    coll = scene.collection

    def new_object(name, data, pass_index=0):
        ob = bpy.data.objects.new(name, data)
        ob.pass_index = pass_index
        coll.objects.link(ob)
        return ob

    def new_material(name):
        m = bpy.data.materials.new(name)
        m.use_nodes = True
        m.node_tree.nodes.clear()
        return m, m.node_tree.nodes, m.node_tree.links

    def value_node(nodes, v):
        # Constants through Value nodes: sockets' soft/hard limits do not clamp them.
        n = nodes.new("ShaderNodeValue")
        n.outputs[0].default_value = v
        return n.outputs[0]

    def coordinates(nodes, links, which):
        # A texture coordinate (Generated, Object, ...) split into X, Y, Z.
        tc = nodes.new("ShaderNodeTexCoord")
        sep = nodes.new("ShaderNodeSeparateXYZ")
        links.new(tc.outputs[which], sep.inputs[0])
        return sep

    def math_node(nodes, operation):
        n = nodes.new("ShaderNodeMath")
        n.operation = operation
        return n

    def object_attribute(nodes, name, output="Color"):
        n = nodes.new("ShaderNodeAttribute")
        n.attribute_type = "OBJECT"
        n.attribute_name = name
        return n.outputs[output]

    def principled(nodes, links, base, alpha, specular):
        p = nodes.new("ShaderNodeBsdfPrincipled")
        p.distribution = "GGX"
        defaults = {"Metallic": 0.0, "Subsurface": 0.0, "Specular Tint": 0.0, "Anisotropic": 0.0, "Sheen": 0.0,
                    "Clearcoat": 0.0, "Transmission": 0.0, "Transmission Roughness": 0.0,
                    "Emission Strength": 0.0, "Alpha": 1.0}
        for k, v in defaults.items():
            if k in p.inputs:
                p.inputs[k].default_value = v
        if "Emission" in p.inputs:
            p.inputs["Emission"].default_value = (0.0, 0.0, 0.0, 1.0)
        links.new(value_node(nodes, math.sqrt(alpha)), p.inputs["Roughness"])
        links.new(specular, p.inputs["Specular"])
        if s["diffuse"] == "principled":
            links.new(base, p.inputs["Base Color"])
            return p
        # Lambert: Principled's specular alone (a black base colour weighs its diffuse
        # closure to nothing; at Metallic 0 the specular does not depend on it) plus a
        # Lambert lobe of the base colour, as the fast renderer shades.
        p.inputs["Base Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        d = nodes.new("ShaderNodeBsdfDiffuse")
        links.new(base, d.inputs["Color"])
        d.inputs["Roughness"].default_value = 0.0
        add = nodes.new("ShaderNodeAddShader")
        links.new(p.outputs[0], add.inputs[0])
        links.new(d.outputs[0], add.inputs[1])
        return add

    def finish(nodes, links, shader):
        out = nodes.new("ShaderNodeOutputMaterial")
        out.target = "ALL"
        links.new(shader, out.inputs["Surface"])

    # --- world: the sky's radiance from the view direction (world Generated = ray direction)
    world = bpy.data.worlds.new("gb_sky")
    scene.world = world
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    nodes.clear()
    sep = coordinates(nodes, links, "Generated")
    zpos = math_node(nodes, "MAXIMUM")
    links.new(sep.outputs["Z"], zpos.inputs[0])
    zpos.inputs[1].default_value = 0.0
    bg = nodes.new("ShaderNodeBackground")
    bg.inputs["Strength"].default_value = 1.0
    sc = s["sky_scale"]
    if s["sky_kind"] == "clear":
        root = nodes.new("ShaderNodeMath")
        root.operation = "SQRT"
        links.new(zpos.outputs[0], root.inputs[0])
        # s * (horizon * (1 - t) + zenith * t) = t * s (zenith - horizon) + s horizon
        mad = nodes.new("ShaderNodeVectorMath")
        mad.operation = "MULTIPLY_ADD"
        links.new(root.outputs[0], mad.inputs[0])
        mad.inputs[1].default_value = [sc * (zc - hc) for zc, hc in zip(s["sky_zenith"], s["sky_horizon"])]
        mad.inputs[2].default_value = [sc * hc for hc in s["sky_horizon"]]
        links.new(mad.outputs["Vector"], bg.inputs["Color"])
    else:
        # s (1 + 2 z) / 3 = z (2 s / 3) + s / 3, grey
        mad = nodes.new("ShaderNodeMath")
        mad.operation = "MULTIPLY_ADD"
        mad.use_clamp = False
        links.new(zpos.outputs[0], mad.inputs[0])
        mad.inputs[1].default_value = 2.0 * sc / 3.0
        mad.inputs[2].default_value = sc / 3.0
        links.new(mad.outputs[0], bg.inputs["Color"])
    wout = nodes.new("ShaderNodeOutputWorld")
    links.new(bg.outputs["Background"], wout.inputs["Surface"])

    # --- camera: OpenCV pose -> Blender's camera frame
    cd = bpy.data.cameras.new("gb_camera")
    cd.type = "PERSP"
    cd.sensor_fit = "HORIZONTAL"
    sw = s["sensor_width_mm"]
    lens = s["fx"] * sw / W
    # Blender keeps lens and sensor >= 1 mm: scale both (and the f-number with them, so the
    # aperture's diameter lens / N stays) when either is smaller; the view is unchanged.
    k = max(1.0, 1.0 / lens, 1.0 / sw)
    cd.sensor_width = sw * k
    cd.sensor_height = sw * k * H / W
    cd.lens = lens * k
    if abs(cd.lens - lens * k) > 1e-4 * lens * k or abs(cd.sensor_width - sw * k) > 1e-4 * sw * k:
        raise SceneError("Blender cannot take a lens of %g mm on a sensor %g mm wide" % (lens, sw))
    # Shift in units of the fitted side: the width under sensor fit HORIZONTAL (Cycles' and
    # Blender's viewplane), which is max(W, H) for landscape images.
    cd.shift_x = -(s["cx"] - W / 2.0) / W
    cd.shift_y = (s["cy"] - H / 2.0) / W
    cd.clip_start = 1e-3
    cd.clip_end = 1e5
    cd.dof.use_dof = s["f_number"] > 0
    if s["f_number"] > 0:
        cd.dof.focus_distance = s["focus_distance"]
        cd.dof.aperture_fstop = s["f_number"] * k
        cd.dof.aperture_blades = 0
        cd.dof.aperture_rotation = 0.0
        cd.dof.aperture_ratio = 1.0
    cam = new_object("gb_camera", cd)
    p = s["pose"]
    pose = Matrix([p[0:4], p[4:8], p[8:12], p[12:16]])
    cam.matrix_world = pose @ Matrix.Diagonal((1.0, -1.0, -1.0, 1.0))
    scene.camera = cam

    # --- sun: light along -direction (a sun shines down its local -z)
    ld = bpy.data.lights.new("gb_sun", "SUN")
    ld.energy = s["sun_irradiance"]
    ld.color = s["sun_colour"]
    ld.angle = math.radians(s["sun_angle_deg"])
    sun = new_object("gb_sun", ld)
    sun.rotation_mode = "QUATERNION"
    sun.rotation_quaternion = Vector(s["sun_direction"]).to_track_quat("Z", "Y")

    # --- ground: a horizontal diffuse square, pass index 0
    hs, gz = s["ground_half_size"], s["ground_z"]
    if hs > 0:
        gm = bpy.data.meshes.new("gb_ground")
        gm.from_pydata([(-hs, -hs, gz), (hs, -hs, gz), (hs, hs, gz), (-hs, hs, gz)], [], [(0, 1, 2, 3)])
        mat, nodes, links = new_material("gb_ground")
        d = nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = list(s["ground_reflectance"]) + [1.0]
        d.inputs["Roughness"].default_value = 0.0
        finish(nodes, links, d.outputs[0])
        gm.materials.append(mat)
        new_object("gb_ground", gm, 0)

    # --- berries: one unit UV sphere, smooth shaded, linked by every berry
    if s["berries"]:
        ns, nr = SPHERE_SEGMENTS, SPHERE_RINGS
        verts = [(0.0, 0.0, 1.0)]
        for i in range(1, nr):
            th = math.pi * i / nr
            for j in range(ns):
                ph = 2.0 * math.pi * j / ns
                verts.append((math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)))
        south = len(verts)
        verts.append((0.0, 0.0, -1.0))

        def ring(i, j):  # i in 1..nr-1
            return 1 + (i - 1) * ns + j % ns

        faces = [(0, ring(1, j), ring(1, j + 1)) for j in range(ns)]
        for i in range(1, nr - 1):
            faces += [(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)) for j in range(ns)]
        faces += [(ring(nr - 1, j), south, ring(nr - 1, j + 1)) for j in range(ns)]
        sm = bpy.data.meshes.new("gb_berry")
        sm.from_pydata(verts, [], faces)
        sm.polygons.foreach_set("use_smooth", [True] * len(sm.polygons))
        sm.update()
        mat, nodes, links = new_material("gb_berry")
        pr = principled(nodes, links, object_attribute(nodes, "gb_albedo"), s["berry_alpha"],
                        value_node(nodes, s["berry_f0"] / 0.08))
        tr = nodes.new("ShaderNodeBsdfTranslucent")
        links.new(object_attribute(nodes, "gb_transmittance"), tr.inputs["Color"])
        add = nodes.new("ShaderNodeAddShader")
        links.new(pr.outputs[0], add.inputs[0])
        links.new(tr.outputs[0], add.inputs[1])
        # Light that the skin transmits crosses the flesh and leaves through the far
        # side: the sphere's inside faces pass everything out (a white translucent
        # BSDF) and reflect nothing back in, so the berry transmits once, as the fast
        # renderer's translucency term assumes (no light trapped inside the sphere).
        geo = nodes.new("ShaderNodeNewGeometry")
        out_tr = nodes.new("ShaderNodeBsdfTranslucent")
        out_tr.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        mix = nodes.new("ShaderNodeMixShader")
        links.new(geo.outputs["Backfacing"], mix.inputs[0])
        links.new(add.outputs[0], mix.inputs[1])
        links.new(out_tr.outputs[0], mix.inputs[2])
        finish(nodes, links, mix.outputs[0])
        sm.materials.append(mat)
        for i, b in enumerate(s["berries"]):
            if b["radius"] <= 0:
                continue
            ob = new_object("gb_berry_%d" % i, sm, b["id"])
            ob.location = b["centre"]
            ob.scale = (b["radius"],) * 3
            ob["gb_albedo"] = b["albedo"]
            ob["gb_transmittance"] = b["transmittance"]

    # --- cylinders: one capped unit cylinder (radius 1, z in [0, 1]) linked by every one
    if s["cylinders"]:
        n = CYLINDER_SIDES
        ring0 = [(math.cos(2 * math.pi * j / n), math.sin(2 * math.pi * j / n)) for j in range(n)]
        verts = [(x, y, 0.0) for x, y in ring0] + [(x, y, 1.0) for x, y in ring0]   # side
        verts += [(x, y, 0.0) for x, y in ring0] + [(x, y, 1.0) for x, y in ring0]  # caps: own vertices
        faces = [(n + j, j, (j + 1) % n, n + (j + 1) % n) for j in range(n)]
        faces.append(tuple(2 * n + j for j in reversed(range(n))))   # bottom, normal -z
        faces.append(tuple(3 * n + j for j in range(n)))             # top, normal +z
        cm = bpy.data.meshes.new("gb_cylinder")
        cm.from_pydata(verts, [], faces)
        cm.polygons.foreach_set("use_smooth", [True] * n + [False, False])
        cm.update()
        mat, nodes, links = new_material("gb_cylinder")
        d = nodes.new("ShaderNodeBsdfDiffuse")
        albedo = object_attribute(nodes, "gb_albedo")
        if "wood_png" in s:
            # The wood texture (wood_atlas.h): the unit cylinder's own coordinates give the
            # fraction along it (z) and the angle about it (atan2(y, x), x = the exported
            # x_axis); the object's rectangle turns them into the atlas's uv.
            xyz = coordinates(nodes, links, "Object")
            angle = math_node(nodes, "ARCTAN2")
            links.new(xyz.outputs["Y"], angle.inputs[0])
            links.new(xyz.outputs["X"], angle.inputs[1])
            around = math_node(nodes, "MULTIPLY_ADD")  # angle / 2 pi + 1 / 2
            links.new(angle.outputs[0], around.inputs[0])
            links.new(value_node(nodes, 1 / (2 * math.pi)), around.inputs[1])
            links.new(value_node(nodes, 0.5), around.inputs[2])
            local = nodes.new("ShaderNodeCombineXYZ")
            links.new(xyz.outputs["Z"], local.inputs["X"])
            links.new(around.outputs[0], local.inputs["Y"])
            steps = nodes.new("ShaderNodeVectorMath")
            steps.operation = "MULTIPLY_ADD"  # origin + (along, around) x steps, in texels
            links.new(local.outputs[0], steps.inputs[0])
            links.new(object_attribute(nodes, "gb_atlas_steps", "Vector"), steps.inputs[1])
            links.new(object_attribute(nodes, "gb_atlas_origin", "Vector"), steps.inputs[2])
            uv = nodes.new("ShaderNodeVectorMath")
            uv.operation = "MULTIPLY"
            links.new(steps.outputs[0], uv.inputs[0])
            uv.inputs[1].default_value = (1.0 / s["wood_width"], 1.0 / s["wood_height"], 0.0)
            img = nodes.new("ShaderNodeTexImage")
            img.image = bpy.data.images.load(s["wood_png"])
            img.image.colorspace_settings.name = "Non-Color"
            img.interpolation = "Linear"
            img.extension = "EXTEND"
            links.new(uv.outputs[0], img.inputs["Vector"])
            factor = math_node(nodes, "MULTIPLY_ADD")  # 1 + a (2 t - 1) = 2 a t + 1 - a
            links.new(img.outputs["Color"], factor.inputs[0])
            links.new(value_node(nodes, 2 * s["wood_amplitude"]), factor.inputs[1])
            links.new(value_node(nodes, 1 - s["wood_amplitude"]), factor.inputs[2])
            mix = nodes.new("ShaderNodeMixRGB")
            mix.blend_type = "MULTIPLY"
            mix.use_clamp = True  # as the appearance model clamps each channel to [0, 1]
            mix.inputs["Fac"].default_value = 1.0
            links.new(albedo, mix.inputs["Color1"])
            links.new(factor.outputs[0], mix.inputs["Color2"])
            albedo = mix.outputs["Color"]
        links.new(albedo, d.inputs["Color"])
        d.inputs["Roughness"].default_value = 0.0
        finish(nodes, links, d.outputs[0])
        cm.materials.append(mat)
        for i, cy in enumerate(s["cylinders"]):
            a, e = Vector(cy["start"]), Vector(cy["end"])
            length = (e - a).length
            if cy["radius"] <= 0 or length <= 0:
                continue
            axis = (e - a).normalized()
            if "x_axis" in cy:  # the atlas's frame: x_axis at angle 0, axis x x_axis at pi / 2
                x = Vector(cy["x_axis"]).normalized()
                y = axis.cross(x)
                rot = Matrix((x, y, axis)).transposed().to_4x4()
            else:
                rot = axis.to_track_quat("Z", "Y").to_matrix().to_4x4()
            ob = new_object("gb_cylinder_%d" % i, cm, cy["id"])
            ob.matrix_world = Matrix.Translation(a) @ rot @ Matrix.Diagonal((cy["radius"], cy["radius"], length, 1.0))
            ob["gb_albedo"] = cy["albedo"]
            if "x_axis" in cy:
                ob["gb_atlas_origin"] = cy["atlas_origin"]
                ob["gb_atlas_steps"] = cy["atlas_steps"]

    # --- leaves: one mesh each, flat shaded, textured through their uv
    if s["leaves"]:
        def load_data_image(path):
            img = bpy.data.images.load(path, check_existing=False)
            img.colorspace_settings.name = "Non-Color"
            img.alpha_mode = "CHANNEL_PACKED"
            if img.size[0] <= 0 or img.size[1] <= 0:
                raise SceneError("cannot read the image %s" % path)
            return img

        mat, nodes, links = new_material("gb_leaf")

        def texture(img):
            t = nodes.new("ShaderNodeTexImage")
            t.image = img
            t.interpolation = "Linear"
            t.extension = "EXTEND"
            t.projection = "FLAT"
            return t.outputs["Color"]

        albedo = texture(load_data_image(s["leaf_albedo_png"]))
        transmittance = texture(load_data_image(s["leaf_transmittance_png"]))
        geo = nodes.new("ShaderNodeNewGeometry")
        # base = albedo * (1 + (back - 1) * backfacing)
        fac = nodes.new("ShaderNodeMath")
        fac.operation = "MULTIPLY_ADD"
        links.new(geo.outputs["Backfacing"], fac.inputs[0])
        fac.inputs[1].default_value = s["leaf_back"] - 1.0
        fac.inputs[2].default_value = 1.0
        base = nodes.new("ShaderNodeVectorMath")
        base.operation = "SCALE"
        links.new(albedo, base.inputs[0])
        links.new(fac.outputs[0], base.inputs["Scale"])
        # specular = f0 / 0.08 * (1 - backfacing)
        sp = s["leaf_f0"] / 0.08
        spec = nodes.new("ShaderNodeMath")
        spec.operation = "MULTIPLY_ADD"
        links.new(geo.outputs["Backfacing"], spec.inputs[0])
        spec.inputs[1].default_value = -sp
        spec.inputs[2].default_value = sp
        pr = principled(nodes, links, base.outputs["Vector"], s["leaf_alpha"], spec.outputs[0])
        tr = nodes.new("ShaderNodeBsdfTranslucent")
        links.new(transmittance, tr.inputs["Color"])
        add = nodes.new("ShaderNodeAddShader")
        links.new(pr.outputs[0], add.inputs[0])
        links.new(tr.outputs[0], add.inputs[1])
        finish(nodes, links, add.outputs[0])

        for i, lf in enumerate(s["leaves"]):
            p = lf["path"]
            try:
                v = np.asarray(lf["vertices"], dtype=np.float64)
                uv = np.asarray(lf["uv"], dtype=np.float64)
                t = np.asarray(lf["triangles"], dtype=np.int64)
            except (ValueError, TypeError):
                raise SceneError("%s: vertices, uv or triangles are not rectangular arrays of numbers" % p)
            nv = len(v)
            if nv and (v.ndim != 2 or v.shape[1] != 3 or not np.isfinite(v).all()):
                raise SceneError("'%s.vertices' is not a list of [x, y, z]" % p)
            if nv and (uv.ndim != 2 or uv.shape[1] != 2 or not np.isfinite(uv).all()):
                raise SceneError("'%s.uv' is not a list of [u, v]" % p)
            if len(t) and (t.ndim != 2 or t.shape[1] != 3):
                raise SceneError("'%s.triangles' is not a list of [a, b, c]" % p)
            if len(t) == 0:
                continue
            if t.min() < 0 or t.max() >= nv:
                raise SceneError("'%s.triangles' refers to a vertex outside [0, %d]" % (p, nv - 1))
            lm = bpy.data.meshes.new("gb_leaf_%d" % i)
            try:  # bulk arrays: about 4x faster than from_pydata on large meshes
                nt = len(t)
                lm.vertices.add(nv)
                lm.vertices.foreach_set("co", v.astype(np.float32).reshape(-1))
                lm.loops.add(3 * nt)
                lm.loops.foreach_set("vertex_index", t.astype(np.int32).reshape(-1))
                lm.polygons.add(nt)
                lm.polygons.foreach_set("loop_start", np.arange(0, 3 * nt, 3, dtype=np.int32))
                lm.polygons.foreach_set("loop_total", np.full(nt, 3, dtype=np.int32))
                lm.update(calc_edges=True)
            except (AttributeError, TypeError, RuntimeError):  # a Blender whose loop_total is read-only
                bpy.data.meshes.remove(lm)
                lm = bpy.data.meshes.new("gb_leaf_%d" % i)
                lm.from_pydata(v.tolist(), [], t.tolist())
            if len(lm.polygons) != len(t) or len(lm.loops) != 3 * len(t):
                raise SceneError("%s: Blender made %d faces of %d triangles" % (p, len(lm.polygons), len(t)))
            uvl = lm.uv_layers.new(name="UVMap")
            uvl.data.foreach_set("uv", uv[t.reshape(-1)].astype(np.float32).reshape(-1))
            lm.polygons.foreach_set("use_smooth", [False] * len(t))
            lm.update()
            lm.materials.append(mat)
            new_object("gb_leaf_%d" % i, lm, lf["id"])

    # --- compositor: Combined and IndexOB to 32-bit float OpenEXR in a temporary folder
    tmp = tempfile.mkdtemp(prefix=".cycles_scene_", dir=folder)
    try:
        scene.use_nodes = True
        tree = scene.node_tree
        tree.nodes.clear()
        rl = tree.nodes.new("CompositorNodeRLayers")
        rl.scene = scene
        rl.layer = view_layer.name
        if "IndexOB" not in rl.outputs:
            raise SceneError("the Render Layers node has no IndexOB output")
        fo = tree.nodes.new("CompositorNodeOutputFile")
        fo.base_path = tmp
        fo.format.file_format = "OPEN_EXR"
        fo.format.color_mode = "RGB"
        fo.format.color_depth = "32"
        fo.format.exr_codec = "ZIP"
        fo.file_slots[0].path = "colour_"
        fo.file_slots.new("index_")
        tree.links.new(rl.outputs["Image"], fo.inputs[0])
        tree.links.new(rl.outputs["IndexOB"], fo.inputs[1])
        comp = tree.nodes.new("CompositorNodeComposite")
        tree.links.new(rl.outputs["Image"], comp.inputs["Image"])

        result = bpy.ops.render.render(write_still=False)
        if "FINISHED" not in result:
            raise SceneError("the render did not finish (%s)" % ", ".join(sorted(result)))

        def read_exr(prefix):
            names = sorted(f for f in os.listdir(tmp) if f.startswith(prefix) and f.endswith(".exr"))
            if not names:
                raise SceneError("the compositor wrote no %s*.exr" % prefix)
            img = bpy.data.images.load(os.path.join(tmp, names[-1]), check_existing=False)
            try:
                if tuple(img.size) != (W, H):
                    raise SceneError("%s is %d x %d, want %d x %d" % (names[-1], img.size[0], img.size[1], W, H))
                buf = np.empty(W * H * 4, dtype=np.float32)
                img.pixels.foreach_get(buf)
            finally:
                bpy.data.images.remove(img)
            return buf.reshape(H, W, 4)[::-1]  # Blender's rows are bottom first

        rgba = read_exr("colour_")
        # The object index pass holds the first sample's object, drawn anywhere in the
        # pixel: the labels come from a second render of one sample through each
        # pixel's centre (a box filter 0.01 px wide), the ray the exact labels take.
        scene.cycles.samples = 1
        scene.cycles.filter_width = 0.01
        scene.camera.data.dof.use_dof = False  # through the pinhole, as the exact labels
        result = bpy.ops.render.render(write_still=False)
        if "FINISHED" not in result:
            raise SceneError("the label render did not finish (%s)" % ", ".join(sorted(result)))
        idx = read_exr("index_")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    rgb = np.ascontiguousarray(rgba[:, :, :3], dtype="<f4")
    if not np.isfinite(rgb).all():
        raise SceneError("the Combined pass holds non-finite values")
    ids = np.ascontiguousarray(np.rint(idx[:, :, 0]), dtype=np.float64)
    if ids.min() < 0 or ids.max() > MAX_ID:
        raise SceneError("the object index pass holds values outside [0, %d]" % MAX_ID)
    ids = ids.astype("<i4")

    def write(path, arr):
        part = path + ".part"
        arr.tofile(part)
        os.replace(part, path)

    write(s["out_colour"], rgb)
    write(s["out_index"], ids)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 1:
        raise SceneError("usage: blender -b --factory-startup -noaudio -P cycles_scene.py -- <scene.json>")
    path = os.path.abspath(argv[0])
    try:
        with open(path, "r", encoding="utf-8") as f:
            doc = json.load(f)
    except OSError as e:
        raise SceneError("cannot read %s: %s" % (path, e.strerror or e))
    except ValueError as e:
        raise SceneError("%s is not JSON: %s" % (path, e))
    folder = os.path.dirname(path)
    s = parse(doc, folder)
    for f in (s["out_colour"], s["out_index"]):
        if os.path.exists(f):
            os.remove(f)
    build_and_render(s, folder)


if __name__ == "__main__":
    try:
        main()
    except SceneError as e:
        fail(e)
    except SystemExit:
        raise
    except BaseException as e:  # anything Blender or Python raises: one line, exit 2
        fail("%s: %s" % (type(e).__name__, e))

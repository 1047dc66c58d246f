"""blender_scenes.py: small glTF test scenes built in Blender from code, with Cycles references.

    blender -b --factory-startup --python tools/blender_scenes.py -- OUTDIR [SCENE...]

For each scene (all, or those named) it writes OUTDIR/SCENE/:
    scene.glb            Blender's glTF exporter as a user runs it: binary, +Y up, cameras and
                         punctual lights included, light units at their default (683 lm/W)
    scene.obj, .mtl      the same geometry through Blender's OBJ exporter (-Z forward, +Y up:
                         the glTF's axes; the PBR keys Pr/Pm/Ke on)
    scene.cfg            the OBJ route's scene file, written here from the Blender camera and
                         light data (the conversions are in obj_cfg below)
    cycles-*.png, .exr   Cycles renders, one per camera or flythrough frame: PNG is 8-bit sRGB
                         with straight alpha (the silhouette: film transparent), EXR is the
                         linear half-float RGBA radiance (premultiplied) for image means
tests/gltf/ holds these outputs, so that tests/test_gltf_blender.sh runs without Blender.

Blender is set where its models and vkrt's differ so that both compute the same picture:
- Lambert: Cycles 3.4's Principled diffuse is Disney's (darker at grazing angles, brighter back
  towards the light), glTF's is Lambert. A diffuse material here is a Principled BSDF (Specular 0,
  what the exporter reads: KHR_materials_specular with factor 0, no dielectric reflection) on the
  active output for all engines, and a Diffuse BSDF of roughness 0 (Lambert) on a Cycles-only
  output, which Cycles takes before the other (Blender's ntreeShaderOutputNode prefers an exact
  target). The .glb is byte for byte what the Principled material alone exports.
- Colour: view transform Standard, look None, exposure 0, gamma 1 (no Filmic): PNG = sRGB(linear).
- Pixel filter: a box one pixel wide, as vkrt's jittered samples are; no denoiser; no light
  clamping, no glossy filter, caustics on: an unbiased path tracer, as vkrt's.
- Bounces: 4 of every kind (Cycles' max_bounces 0 is direct light alone, as vkrt's max-depth 0);
  scene.cfg says max-depth 4.
- Lights: radius 0 (point, spot) and angle 0 (sun): delta lights. A Blender point light of P W
  is, in Cycles (kernel/light: eval_fac = invarea / (4 pi), invarea 1 at radius 0), a radiant
  intensity of P / (4 pi) W/sr, what the exporter writes as P / (4 pi) * 683 cd; a sun of S W/m^2
  is an irradiance of S W/m^2 (S * 683 lux in the glTF).
What still differs, and is not matched here:
- Glass: Cycles renders a closed mesh of transmission 1 as a solid (refracting in and out); a
  glTF material with KHR_materials_transmission and no KHR_materials_volume (Blender 3.4 writes
  none) is thin-walled. The glass sphere of `materials` is the same in silhouette only.
- Spot lights: Cycles 3.4's spot is P / (4 pi) times cos(angle to the axis) times a smoothstep
  over the outer Blend share of the cone (in cosine); glTF's (inner and outer cone, exported as
  outer * (1 - blend)) and vkrt's (full to 3/4 of the half angle, linear to 0 at it) have no
  cosine. The lights scene's spot has a half angle of 25 degrees: cos 25 = 0.906.
- Principled metals: Cycles' Fresnel of a metallic Principled is its "principled" blend towards
  white at grazing angles, close to glTF's Schlick but not the same.
- The orthographic camera has no scene.cfg line before vkrt reads `ortho`; scene.cfg of the
  cameras scene holds the perspective one.
"""
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector

WIDTH, HEIGHT = 160, 120
SAMPLES = 1024
SEED = 35
BOUNCES = 4
FPS = 24


# ---- scene building ------------------------------------------------------------------------

def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    LAMBERT_NAMES.clear()
    scene = bpy.context.scene
    scene.render.engine = 'CYCLES'
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    scene.render.fps = FPS
    scene.render.film_transparent = True
    cycles = scene.cycles
    cycles.device = 'CPU'
    cycles.samples = SAMPLES
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = SEED
    cycles.use_animated_seed = False
    cycles.pixel_filter_type = 'BOX'
    cycles.filter_width = 1.0
    cycles.max_bounces = BOUNCES
    cycles.diffuse_bounces = cycles.glossy_bounces = cycles.transmission_bounces = BOUNCES
    cycles.transparent_max_bounces = BOUNCES
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0
    cycles.blur_glossy = 0.0
    cycles.caustics_reflective = cycles.caustics_refractive = True
    cycles.light_sampling_threshold = 0.0
    view = scene.view_settings
    view.view_transform, view.look, view.exposure, view.gamma = 'Standard', 'None', 0.0, 1.0
    scene.display_settings.display_device = 'sRGB'
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0, 0, 0, 1)
    background.inputs["Strength"].default_value = 0.0
    scene.world = world
    return scene


def principled(name, base=(0.8, 0.8, 0.8), metallic=0.0, roughness=0.5, specular=0.5,
               transmission=0.0, ior=1.5, emission=(0, 0, 0), strength=1.0):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.distribution = 'GGX'
    bsdf.inputs["Base Color"].default_value = (*base, 1)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Specular"].default_value = specular
    bsdf.inputs["Transmission"].default_value = transmission
    bsdf.inputs["IOR"].default_value = ior
    bsdf.inputs["Emission"].default_value = (*emission, 1)
    bsdf.inputs["Emission Strength"].default_value = strength
    return mat


# Names of the materials lambert() made, whose .mtl entries lose the PBR keys (write_obj).
LAMBERT_NAMES = set()


def lambert(name, base):
    """A Principled BSDF with Specular 0 for the exporter, a Lambert for Cycles (module notes)."""
    LAMBERT_NAMES.add(name)
    mat = principled(name, base=base, specular=0.0)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    shared_output = nodes["Material Output"]
    shared_output.target = 'ALL'
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*base, 1)
    diffuse.inputs["Roughness"].default_value = 0.0
    cycles_output = nodes.new("ShaderNodeOutputMaterial")
    cycles_output.target = 'CYCLES'
    links.new(diffuse.outputs["BSDF"], cycles_output.inputs["Surface"])
    shared_output.is_active_output = True
    return mat


def link(obj):
    bpy.context.scene.collection.objects.link(obj)
    return obj


def mesh_object(name, mesh, location=(0, 0, 0), rotation=(0, 0, 0), scale=(1, 1, 1)):
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    obj.rotation_euler = [math.radians(a) for a in rotation]
    obj.scale = scale
    return link(obj)


def new_mesh(name, add, material, smooth=False, **kwargs):
    """A mesh made by a bpy.ops.mesh.primitive_*_add operator, taken out of its object so that
    several objects can share it (linked duplicates: one glTF mesh, several nodes)."""
    add(**kwargs)
    obj = bpy.context.active_object
    mesh = obj.data
    mesh.name = name
    bpy.data.objects.remove(obj)
    for polygon in mesh.polygons:
        polygon.use_smooth = smooth
    mesh.materials.append(material)
    return mesh


def ground(size, material):
    mesh = new_mesh("ground", bpy.ops.mesh.primitive_plane_add, material, size=size)
    return mesh_object("ground", mesh)


def sphere(name, material, location, radius=0.45):
    mesh = new_mesh(name, bpy.ops.mesh.primitive_uv_sphere_add, material, smooth=True,
                    segments=16, ring_count=8, radius=radius)
    return mesh_object(name, mesh, location)


def look_at(obj, target):
    direction = Vector(target) - obj.location
    obj.rotation_euler = direction.to_track_quat('-Z', 'Y').to_euler()


def camera(name, location, target, lens=50.0, ortho_scale=None):
    data = bpy.data.cameras.new(name)
    data.lens = lens
    data.sensor_fit = 'AUTO'
    if ortho_scale:
        data.type = 'ORTHO'
        data.ortho_scale = ortho_scale
    obj = link(bpy.data.objects.new(name, data))
    obj.location = location
    look_at(obj, target)
    return obj


def light(name, kind, energy, location=(0, 0, 0), target=None, color=(1, 1, 1), **settings):
    data = bpy.data.lights.new(name, kind)
    data.energy = energy
    data.color = color
    if kind == 'SUN':
        data.angle = 0.0
    else:
        data.shadow_soft_size = 0.0
    for key, value in settings.items():
        setattr(data, key, value)
    obj = link(bpy.data.objects.new(name, data))
    obj.location = location
    if target is not None:
        look_at(obj, target)
    return obj


# ---- the scenes ------------------------------------------------------------------------------

def chiral_cone(material):
    """An 8-sided cone whose apex leans off its axis towards +x +y: no mirror maps it onto
    itself, so a mirrored instance shows in the silhouette."""
    mesh = new_mesh("cone", bpy.ops.mesh.primitive_cone_add, material, vertices=8, radius1=0.5,
                    depth=1.2)
    apex = max(mesh.vertices, key=lambda v: v.co.z)
    apex.co = Vector((0.3, 0.2, apex.co.z))
    return mesh


def instance_layout():
    """One cone mesh placed five times (rotated, scaled unevenly, lying, small, mirrored) and the
    sun: the instances scene and the flythrough's set. No ground: the silhouette is the cones'
    alone (a ground behind them would hold them all inside its own outline)."""
    cone = chiral_cone(lambert("cone", (0.8, 0.3, 0.1)))
    mesh_object("cone-plain", cone, (-1.6, 0.0, 0.6))
    mesh_object("cone-turned", cone, (0.0, 1.2, 0.9), rotation=(0, 0, 60), scale=(1, 1, 1.5))
    mesh_object("cone-lying", cone, (1.7, 0.2, 0.5), rotation=(90, 0, 20))
    mesh_object("cone-small", cone, (0.6, -1.2, 0.3), rotation=(0, 0, -30), scale=(0.5, 0.5, 0.5))
    mesh_object("cone-mirrored", cone, (-0.6, -1.0, 0.6), scale=(-1, 1, 1))
    light("sun", 'SUN', 3.0, (0, 0, 5), target=(1.5, 1.0, 0))


def scene_instances():
    instance_layout()
    return [("cam0", camera("camera", (4.5, -5.5, 4.0), (0, 0, 0.4)))]


def scene_materials():
    ground(8, lambert("ground", (0.5, 0.5, 0.5)))
    sphere("diffuse", lambert("diffuse", (0.2, 0.5, 0.8)), (-2.0, 0, 0.45))
    sphere("metal-0.2", principled("metal-0.2", (0.9, 0.7, 0.3), metallic=1, roughness=0.2),
           (-1.0, 0, 0.45))
    sphere("metal-0.5", principled("metal-0.5", (0.9, 0.9, 0.9), metallic=1, roughness=0.5),
           (0.0, 0, 0.45))
    sphere("emissive", principled("emissive", (0, 0, 0), specular=0.0, emission=(1, 0.6, 0.3),
                                  strength=4.0), (1.0, 0, 0.45))
    sphere("glass", principled("glass", (1, 1, 1), roughness=0.0, transmission=1.0, ior=1.5),
           (2.0, 0, 0.45))
    light("sun", 'SUN', 2.0, (0, 0, 5), target=(-1.0, 2.0, 0))
    return [("cam0", camera("camera", (0, -7.5, 2.6), (0, 0, 0.35)))]


def scene_cameras():
    ground(8, lambert("ground", (0.5, 0.5, 0.5)))
    box = new_mesh("box", bpy.ops.mesh.primitive_cube_add, lambert("box", (0.3, 0.6, 0.3)),
                   size=1.0)
    mesh_object("box-a", box, (-1.0, 0.5, 0.5))
    mesh_object("box-b", box, (1.0, -0.5, 0.35), rotation=(0, 0, 35), scale=(1.4, 0.7, 0.7))
    mesh_object("box-c", box, (0.3, 1.5, 1.0), rotation=(0, 0, 10), scale=(0.5, 0.5, 2.0))
    light("sun", 'SUN', 3.0, (0, 0, 5), target=(-1.0, 1.5, 0))
    return [("cam0", camera("perspective", (4.0, -5.0, 3.0), (0, 0, 0.5), lens=35.0)),
            ("cam1", camera("orthographic", (-5.0, -5.0, 5.0), (0, 0, 0.5), ortho_scale=6.0))]


def scene_flythrough():
    """The instances' set seen by a camera keyed at frames 0, 12 and 24 (times 0, 0.5 and 1 s at
    24 fps: the exporter writes frame / fps, and a start at 0 leaves no doubt where the
    flythrough's frame 0 is); Blender's Bezier keys are sampled at every frame by the exporter,
    so frame 8 is a sample between keys."""
    instance_layout()
    cam = camera("flythrough", (5.0, -5.0, 3.0), (0, 0, 0.4))
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 0, 24
    for frame, location in ((0, (5.0, -5.0, 3.0)), (12, (0.0, -6.5, 2.0)), (24, (-5.0, -4.0, 4.0))):
        cam.location = location
        look_at(cam, (0, 0, 0.4))
        cam.keyframe_insert("location", frame=frame)
        cam.keyframe_insert("rotation_euler", frame=frame)
    return [(f"frame{frame:02d}", cam, frame) for frame in (0, 8, 24)]


def scene_lights():
    ground(10, lambert("ground", (0.6, 0.6, 0.6)))
    box = new_mesh("box", bpy.ops.mesh.primitive_cube_add, lambert("box", (0.7, 0.2, 0.2)),
                   size=1.0)
    mesh_object("box", box, (-1.0, 0.3, 0.5), rotation=(0, 0, 20))
    sphere("ball", lambert("ball", (0.2, 0.7, 0.3)), (1.2, 0.0, 0.6), radius=0.6)
    light("point", 'POINT', 600.0, (-1.5, -1.5, 2.5))
    light("spot", 'SPOT', 1000.0, (1.5, 0.5, 3.0), target=(1.3, 0.3, 0.0),
          spot_size=math.radians(50.0), spot_blend=0.25)
    return [("cam0", camera("camera", (0, -7.0, 5.0), (0, 0, 0.3)))]


SCENES = {
    "instances": scene_instances,
    "materials": scene_materials,
    "cameras": scene_cameras,
    "flythrough": scene_flythrough,
    "lights": scene_lights,
}


# ---- export and render ---------------------------------------------------------------------

def y_up(v):
    """Blender's +Z-up coordinates in the glTF's (and the OBJ export's) +Y-up ones."""
    return Vector((v.x, v.z, -v.y))


def fmt(*values):
    return " ".join(f"{x:.6g}" for x in values)


def camera_line(obj):
    """scene.cfg's camera line of a Blender camera: it looks down its local -Z with +Y up; with
    sensor fit AUTO and a wide image its angle is the horizontal field of view."""
    world = obj.matrix_world
    eye = world.translation
    forward = world.to_3x3() @ Vector((0, 0, -1))
    up = world.to_3x3() @ Vector((0, 1, 0))
    line = f"camera eye {fmt(*y_up(eye))}  look {fmt(*y_up(eye + forward))}  up {fmt(*y_up(up))}"
    data = obj.data
    if data.type == 'ORTHO':
        # the view's width (sensor fit AUTO: ortho_scale spans the longer side, here the width)
        return f"# orthographic, for when vkrt reads it: {line}  ortho {data.ortho_scale:.6g}"
    vertical = 2 * math.atan(math.tan(data.angle / 2) * HEIGHT / WIDTH)
    return f"{line}  fov {math.degrees(vertical):.6g}"


def light_line(obj):
    data = obj.data
    world = obj.matrix_world
    axis = y_up(world.to_3x3() @ Vector((0, 0, -1))).normalized()
    position = y_up(world.translation)
    if data.type == 'SUN':  # irradiance in W/m^2, as vkrt's directional light
        return f"light directional {fmt(*axis)}  {fmt(*(c * data.energy for c in data.color))}"
    # radiant intensity P / (4 pi) W/sr (module notes)
    intensity = [c * data.energy / (4 * math.pi) for c in data.color]
    if data.type == 'POINT':
        return f"light point {fmt(*position)}  {fmt(*intensity)}"
    if data.type == 'SPOT':
        half = math.degrees(data.spot_size / 2)
        return f"light spot {fmt(*position)}  {fmt(*axis)}  {half:.6g}  {fmt(*intensity)}"
    raise ValueError(f"no scene.cfg line for a {data.type} light")


# The keys of Blender's PBR extension of the .mtl (export_pbr_extensions).
PBR_KEYS = ("Pr", "Pm", "Ps", "Pc", "Pcr", "aniso", "anisor")


def write_obj(path):
    """Blender's OBJ export, and one change to its .mtl: a Lambert material's entry loses the
    PBR keys. vkrt reads a material with them as `@pbr`, whose non-metal share lies under a
    clear coat of index 1.5 whatever its Ni (docs/materials.md), darker at grazing views; Kd
    alone (Ks is 0: Specular 0) is vkrt's `diffuse`, an exact Lambert. The .glb keeps Specular 0
    as KHR_materials_specular."""
    bpy.ops.wm.obj_export(filepath=path, forward_axis='NEGATIVE_Z', up_axis='Y',
                          export_materials=True, export_pbr_extensions=True, export_uv=False,
                          export_triangulated_mesh=True)
    mtl = os.path.splitext(path)[0] + ".mtl"
    with open(mtl) as f:
        lines = f.read().split("\n")
    kept, material = [], None
    for line in lines:
        if line.startswith("newmtl "):
            material = line.split(None, 1)[1]
        if material in LAMBERT_NAMES and line.split(" ", 1)[0] in PBR_KEYS:
            continue
        kept.append(line)
    with open(mtl, "w") as f:
        f.write("\n".join(kept))


def write_cfg(path, name, views):
    scene = bpy.context.scene
    lines = [f"# tools/blender_scenes.py's '{name}' scene, the OBJ route (Blender's OBJ export);",
             "# lights and cameras converted from Blender's data (tools/blender_scenes.py).",
             "geometry scene.obj",
             f"resolution {WIDTH} {HEIGHT}",
             "samples 64",
             f"max-depth {BOUNCES}",
             "integrator path",
             "environment 0 0 0",
             "output out%02d.png" if len(views) > 1 else "output out.png"]
    lines += [light_line(o) for o in scene.objects if o.type == 'LIGHT']
    for view in views:
        if len(view) > 2:
            scene.frame_set(view[2])
        lines.append(f"# {view[0]}")
        lines.append(camera_line(view[1]))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def render(scene, outdir, views):
    for view in views:
        tag, cam = view[0], view[1]
        if len(view) > 2:
            scene.frame_set(view[2])
        scene.camera = cam
        bpy.ops.render.render()
        image = bpy.data.images["Render Result"]
        settings = scene.render.image_settings
        settings.file_format, settings.color_mode, settings.color_depth = 'PNG', 'RGBA', '8'
        settings.compression = 100
        image.save_render(os.path.join(outdir, f"cycles-{tag}.png"), scene=scene)
        settings.file_format, settings.color_mode, settings.color_depth = 'OPEN_EXR', 'RGBA', '16'
        settings.exr_codec = 'ZIP'
        image.save_render(os.path.join(outdir, f"cycles-{tag}.exr"), scene=scene)


def build(name, outdir):
    os.makedirs(outdir, exist_ok=True)
    scene = reset()
    views = SCENES[name]()
    scene.frame_set(scene.frame_start)
    bpy.ops.export_scene.gltf(filepath=os.path.join(outdir, "scene.glb"), export_format='GLB',
                              export_yup=True, export_cameras=True, export_lights=True)
    write_obj(os.path.join(outdir, "scene.obj"))
    write_cfg(os.path.join(outdir, "scene.cfg"), name, views)
    render(scene, outdir, views)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not argv:
        sys.exit("usage: blender -b --factory-startup --python tools/blender_scenes.py -- OUTDIR "
                 "[SCENE...]")
    names = argv[1:] or list(SCENES)
    for name in names:
        if name not in SCENES:
            sys.exit(f"blender_scenes.py: no scene '{name}' (scenes: {', '.join(SCENES)})")
        build(name, os.path.join(argv[0], name))


main()

"""mitsuba_scene: a vkrt scene (scene.cfg, its OBJ and .mtl) as a Mitsuba 3 scene, and the
integrator that renders it with the light transport vkrt models. Used by tools/reference.

Nothing here comes from vkrt's code: scene.cfg, OBJ and .mtl are read again, in Python, from
their documentation (docs/scene-format.md, docs/materials.md). Mitsuba traces the rays,
evaluates and samples the BSDFs (its diffuse, conductor and dielectric), the lights (its point,
spot and directional emitters), the textures (its bitmap) and the camera (its perspective sensor
and box filter). What Mitsuba lacks is written here, small: the Blinn-Phong BRDF, the unshadowed
ambient light, and an integrator that stops at the first diffuse surface (vkrt has no indirect
diffuse light). docs/speed-vs-accuracy.md lists what matches exactly and what cannot."""
import os

import numpy as np

import mitsuba as mi
import drjit as dr


class SceneError(Exception):
    """A scene this tool cannot read, or cannot express in Mitsuba."""


# ---- scene.cfg ---------------------------------------------------------------------------------

class Config:
    """The parts of a scene.cfg that change the picture (docs/scene-format.md)."""

    def __init__(self):
        self.geometry = None
        self.materials = None
        self.width, self.height = 640, 480
        self.samples = 1
        self.max_depth = 6
        self.environment = (0.0, 0.0, 0.0)
        self.lights = []   # (kind, dict of numbers)
        self.cameras = []  # dict eye, look, up, fov


def read_config(path):
    """Reads a scene.cfg; relative paths in it become relative to its folder."""
    cfg = Config()
    folder = os.path.dirname(os.path.abspath(path))
    with open(path, encoding="utf-8-sig") as f:
        for number, line in enumerate(f, 1):
            words = line.split("#", 1)[0].split()
            if not words:
                continue
            key, args = words[0], words[1:]
            where = f"{path}:{number}"
            nums = lambda: [float(a) for a in args]  # noqa: E731
            if key == "geometry":
                cfg.geometry = os.path.join(folder, args[0])
            elif key == "materials":
                cfg.materials = os.path.join(folder, args[0])
            elif key == "resolution":
                cfg.width, cfg.height = int(args[0]), int(args[1])
            elif key == "samples":
                cfg.samples = int(args[0])
            elif key == "max-depth":
                cfg.max_depth = int(args[0])
            elif key == "environment":
                cfg.environment = tuple(nums())
            elif key == "light":
                v = [float(a) for a in args[1:]]
                kind = args[0]
                layout = {"ambient": ["rgb"], "directional": ["dir", "rgb"],
                          "point": ["pos", "rgb"], "spot": ["pos", "dir", "half_angle", "rgb"]}
                if kind not in layout:
                    raise SceneError(f"{where}: unknown light '{kind}'")
                light, i = {}, 0
                for name in layout[kind]:
                    n = 1 if name == "half_angle" else 3
                    light[name] = v[i] if n == 1 else v[i:i + 3]
                    i += n
                cfg.lights.append((kind, light))
            elif key == "camera":
                parts = dict(zip(args[0::4], [args[i + 1:i + 4] for i in range(0, len(args), 4)]))
                fov_at = args.index("fov")
                cfg.cameras.append({"eye": [float(x) for x in parts["eye"]],
                                    "look": [float(x) for x in parts["look"]],
                                    "up": [float(x) for x in parts["up"]],
                                    "fov": float(args[fov_at + 1])})
            elif key in ("accel", "output"):
                pass  # no effect on the picture
            else:
                raise SceneError(f"{where}: unknown keyword '{key}'")
    if cfg.geometry is None or not cfg.cameras:
        raise SceneError(f"{path}: needs a geometry and a camera line")
    return cfg


# ---- OBJ and .mtl ------------------------------------------------------------------------------

class Material:
    """One .mtl material with the defaults vkrt gives absent fields, or a material file entry
    (which names its shader)."""

    def __init__(self, name, folder):
        self.name, self.folder = name, folder
        self.shader = None  # a material file's built-in ("glass") or GLSL file
        self.kd, self.ks, self.ke, self.tf = [0.8] * 3, [0.0] * 3, [0.0] * 3, [1.0] * 3
        self.ns, self.ni, self.d, self.illum = 0.0, 1.0, 1.0, 2
        self.d_given = False  # `d` wins over `Tr` when a material has both (tinyobjloader)
        self.map_kd = self.map_d = None

    def builtin(self):
        """The built-in shader vkrt maps this material to (docs/materials.md's table)."""
        if self.shader:
            return self.shader
        if self.illum in (4, 6, 7):
            return "glass"
        if self.illum in (3, 5):
            return "mirror"
        if any(self.ke) and not any(self.kd) and not any(self.ks) and not self.map_kd:
            return "emissive"
        if self.illum >= 2 and any(self.ks) and self.ns > 0:
            return "phong"
        return "textured" if self.map_kd else "diffuse"


DEFAULT_MATERIAL = Material("(default)", ".")


def find_file(folder, name):
    """A texture named in an .mtl: as written, else with '/' for '\\' and the case ignored."""
    path = os.path.join(folder, name.replace("\\", "/"))
    if os.path.exists(path):
        return path
    parent, base = os.path.split(path)
    for entry in os.listdir(parent or "."):
        if entry.lower() == base.lower():
            return os.path.join(parent, entry)
    raise SceneError(f"texture '{name}' not found beside {folder}")


def read_mtl(path, materials):
    folder = os.path.dirname(path)
    m = None
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            w = line.split("#", 1)[0].split()
            if not w:
                continue
            key, args = w[0], w[1:]
            if key == "newmtl":
                m = materials[" ".join(args)] = Material(" ".join(args), folder)
            elif m is None:
                continue
            elif key in ("Kd", "Ks", "Ke", "Tf") and len(args) >= 3:
                setattr(m, key.lower(), [float(x) for x in args[:3]])
            elif key == "Ns":
                m.ns = float(args[0])
            elif key == "Ni":
                m.ni = float(args[0])
            elif key == "d":
                m.d, m.d_given = float(args[0]), True
            elif key == "Tr" and not m.d_given:
                m.d = 1.0 - float(args[0])
            elif key == "illum":
                m.illum = int(args[0])
            elif key == "map_Kd":
                m.map_kd = find_file(folder, args[-1])
            elif key == "map_d":
                m.map_d = find_file(folder, args[-1])


BUILTINS = ("diffuse", "textured", "phong", "mirror", "glass", "emissive")


def read_material_file(path):
    """The entries of a material file (docs/material-file.md) as Materials: those of the built-in
    shaders read their numbers in the .mtl layout (docs/materials.md), texture slot 0 is the
    colour map and 1 the coverage map. Entries with GLSL shaders keep the shader's path, and are
    refused if a triangle uses them."""
    folder = os.path.dirname(os.path.abspath(path))
    out = {}
    with open(path, encoding="utf-8-sig") as f:
        for number, line in enumerate(f, 1):
            w = line.split("#", 1)[0].split()
            if not w:
                continue
            name, count = w[0], int(w[1])
            textures = [os.path.join(folder, t) for t in w[2:2 + count]]
            shader = w[2 + count]
            p = [float(x) for x in w[3 + count:]] + [0.0] * 16
            m = Material(name, folder)
            m.shader = shader[1:] if shader.startswith("@") else os.path.join(folder, shader)
            m.where = f"{path}:{number}"
            m.kd, m.d, m.ks, m.ns, m.ke = p[0:3], 1.0 - p[3], p[4:7], p[7], p[8:11]
            m.ni, m.tf = p[11], p[12:15]
            m.map_kd = textures[0] if textures else None
            m.map_d = textures[1] if len(textures) > 1 else None
            out[name] = m
    return out


def read_obj(path):
    """The triangles of an OBJ, grouped by material: {material name: {"p": [n, 3, 3] positions,
    "n": normals or None per triangle, "uv": [n, 3, 2] or None}}, and the .mtl materials.
    Polygons become triangle fans, as in vkrt."""
    folder = os.path.dirname(path)
    v, vt, vn = [], [], []
    materials, groups = {}, {}

    def resolve(i, count):  # 1-based, or negative: counted back from the records read so far
        return i - 1 if i > 0 else count + i

    current = None
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            w = line.split("#", 1)[0].split()
            if not w:
                continue
            key = w[0]
            if key == "v":
                v.append([float(x) for x in w[1:4]])
            elif key == "vt":
                vt.append([float(x) for x in w[1:3]] + [0.0] * (2 - len(w[1:3])))
            elif key == "vn":
                vn.append([float(x) for x in w[1:4]])
            elif key == "f":
                corners = []
                for c in w[1:]:
                    idx = (c.split("/") + ["", ""])[:3]
                    corners.append([resolve(int(i), len(table)) if i else -1
                                    for i, table in zip(idx, (v, vt, vn))])
                g = groups.setdefault(current, [])
                for k in range(1, len(corners) - 1):
                    g.append((corners[0], corners[k], corners[k + 1]))
            elif key == "usemtl":
                current = " ".join(w[1:])
            elif key == "mtllib":
                mtl = os.path.join(folder, " ".join(w[1:]))
                if os.path.exists(mtl):
                    read_mtl(mtl, materials)
    v, vt, vn = np.array(v, np.float64), np.array(vt, np.float64), np.array(vn, np.float64)

    out = {}
    for name, tris in groups.items():
        idx = np.array(tris, np.int64)  # [n, 3 corners, (v, vt, vn)], -1: absent
        with_uv = bool(len(vt)) and bool((idx[:, :, 1] >= 0).all())
        with_n = (idx[:, :, 2] >= 0).all(axis=1) if len(vn) else np.zeros(len(idx), bool)
        out[name] = {"p": v[idx[:, :, 0]],
                     "uv": vt[idx[:, :, 1]] if with_uv else None,
                     "n": vn[np.where(idx[:, :, 2] >= 0, idx[:, :, 2], 0)] if len(vn) else None,
                     "has_n": with_n}
    return out, materials


# ---- Mitsuba objects ---------------------------------------------------------------------------

def rgb(value):
    return {"type": "rgb", "value": [float(x) for x in value]}


def texture_times(path, factor):
    """Mitsuba's bitmap texture of an sRGB image decoded to linear by Mitsuba (per texel, before
    filtering, as vkrt does), times factor (Kd); bilinear, repeating."""
    bitmap = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32,
                                     srgb_gamma=False)
    texels = np.array(bitmap) * np.array(factor, np.float32)
    return {"type": "bitmap", "bitmap": mi.Bitmap(texels.astype(np.float32)), "raw": True,
            "filter_type": "bilinear", "wrap_mode": "repeat"}


def coverage_texture(path):
    bitmap = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.Y, mi.Struct.Type.Float32,
                                     srgb_gamma=False)
    return {"type": "bitmap", "bitmap": bitmap, "raw": True, "filter_type": "bilinear",
            "wrap_mode": "repeat"}


def bsdf_for(m):
    """The Mitsuba BSDF of a material, mapped as vkrt maps it; vkrt's surfaces are two-sided,
    so the one-sided Mitsuba BSDFs are wrapped in `twosided`."""
    kind = m.builtin()
    if kind not in BUILTINS:
        raise SceneError(f"{getattr(m, 'where', m.name)}: material '{m.name}' uses shader "
                         f"{kind}, which has no Mitsuba counterpart")
    # @diffuse reads no texture; the others multiply Kd by map_Kd (mtl_diffuse).
    textured = m.map_kd and kind != "diffuse"
    albedo = texture_times(m.map_kd, m.kd) if textured else rgb(m.kd)
    if kind in ("diffuse", "textured", "emissive"):
        bsdf = {"type": "twosided", "bsdf": {"type": "diffuse",
                                              "reflectance": rgb([0, 0, 0]) if kind == "emissive"
                                              else albedo}}
    elif kind == "phong":
        bsdf = {"type": "vkrt_blinn_phong", "kd": albedo, "ks": rgb(m.ks), "ns": m.ns}
    elif kind == "mirror":
        mirror = {"type": "conductor", "material": "none", "specular_reflectance": rgb(m.ks)}
        if not any(m.kd):
            bsdf = {"type": "twosided", "bsdf": mirror}
        else:
            # Kd/pi plus a mirror of Ks: an even blend of twice each (blendbsdf averages; it
            # picks one of the two at random when sampled, so the mirror's weight is 2 Ks
            # half of the time).
            double = 2.0 * np.array(m.kd)
            diffuse = {"type": "diffuse", "reflectance": texture_times(m.map_kd, double)
                       if m.map_kd else rgb(double)}
            mirror["specular_reflectance"] = rgb(2.0 * np.array(m.ks))
            bsdf = {"type": "twosided", "bsdf": {"type": "blendbsdf", "weight": 0.5,
                                                  "bsdf_0": diffuse, "bsdf_1": mirror}}
    elif kind == "glass":
        tint = m.tf if any(m.tf) else [1.0, 1.0, 1.0]
        bsdf = {"type": "dielectric", "int_ior": m.ni if m.ni > 0 else 1.5, "ext_ior": 1.0,
                "specular_transmittance": rgb(tint)}
    if kind in ("diffuse", "textured", "phong") and (m.d < 1.0 or m.map_d):
        opacity = coverage_texture(m.map_d) if m.map_d else m.d
        if m.map_d and m.d < 1.0:
            raise SceneError(f"material '{m.name}': d < 1 together with map_d is not mapped")
        bsdf = {"type": "mask", "opacity": opacity, "bsdf": bsdf}
    return bsdf


def mesh_for(name, tris, with_normals, bsdf, emission):
    """A Mitsuba mesh of triangles [n, 3, 3] with per-corner normals and uvs (corners are not
    shared: OBJ indexes positions, uvs and normals separately)."""
    count = len(tris["p"])
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    if emission is not None:
        props["emitter"] = mi.load_dict({"type": "area", "radiance": rgb(emission)})
    mesh = mi.Mesh(name, 3 * count, count, props=props, has_vertex_normals=with_normals,
                   has_vertex_texcoords=tris["uv"] is not None)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(tris["p"].astype(np.float32).ravel())
    params["faces"] = mi.UInt32(np.arange(3 * count, dtype=np.uint32))
    if with_normals:
        params["vertex_normals"] = mi.Float(tris["n"].astype(np.float32).ravel())
    if tris["uv"] is not None:
        uv = tris["uv"].astype(np.float32).copy()
        uv[:, :, 1] = 1.0 - uv[:, :, 1]  # OBJ's v grows upwards, Mitsuba's bitmap rows downwards
        params["vertex_texcoords"] = mi.Float(uv.ravel())
    params.update()
    return mesh


def look_at(origin, target, up):
    return mi.ScalarTransform4f().look_at(origin=mi.ScalarPoint3f(origin),
                                          target=mi.ScalarPoint3f(target),
                                          up=mi.ScalarVector3f(up))


def any_perpendicular(d):
    d = np.array(d, np.float64) / np.linalg.norm(d)
    a = [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0]
    return np.cross(d, a).tolist()


def scene_dict(cfg, frame=0, width=None, height=None, spp=64, seed=0, max_depth=None):
    """The Mitsuba scene dict of a vkrt scene's frame, and the ambient radiance (which the
    integrator adds itself)."""
    groups, materials = read_obj(cfg.geometry)
    environment = cfg.environment
    if cfg.materials:
        file = read_material_file(cfg.materials)
        env = file.pop("environment", None)
        if env is not None:
            if env.shader != "environment":
                raise SceneError(f"{env.where}: environment shader {env.shader} has no Mitsuba "
                                 "counterpart")
            environment = env.kd
        materials.update(file)  # a material file entry wins over the .mtl material
    scene = {"type": "scene"}
    lo = np.min([g["p"].reshape(-1, 3).min(axis=0) for g in groups.values()], axis=0)
    hi = np.max([g["p"].reshape(-1, 3).max(axis=0) for g in groups.values()], axis=0)
    for i, (name, tris) in enumerate(groups.items()):
        m = materials.get(name, DEFAULT_MATERIAL) if name is not None else DEFAULT_MATERIAL
        bsdf = bsdf_for(m)
        emission = m.ke if any(m.ke) else None
        has_n = tris["has_n"]
        for with_normals in (True, False):
            pick = has_n if with_normals else ~has_n
            if not pick.any():
                continue
            part = {"p": tris["p"][pick], "uv": None if tris["uv"] is None else tris["uv"][pick],
                    "n": None if tris["n"] is None else tris["n"][pick]}
            scene[f"mesh{i}_{int(with_normals)}"] = mesh_for(f"{name}", part, with_normals, bsdf,
                                                             emission)
    ambient = np.zeros(3)
    for k, (kind, light) in enumerate(cfg.lights):
        if kind == "ambient":
            ambient += light["rgb"]
        elif kind == "point":
            scene[f"light{k}"] = {"type": "point", "position": light["pos"],
                                  "intensity": rgb(light["rgb"])}
        elif kind == "directional":
            scene[f"light{k}"] = {"type": "directional", "direction": light["dir"],
                                  "irradiance": rgb(light["rgb"])}
        elif kind == "spot":
            pos, d = np.array(light["pos"]), np.array(light["dir"])
            scene[f"light{k}"] = {"type": "spot", "intensity": rgb(light["rgb"]),
                                  "cutoff_angle": light["half_angle"],
                                  "beam_width": 0.75 * light["half_angle"],
                                  "to_world": look_at(pos, pos + d, any_perpendicular(d))}
    if any(environment):
        scene["environment"] = {"type": "constant", "radiance": rgb(environment)}
    cam = cfg.cameras[frame]
    centre = (lo + hi) / 2
    extent = float(np.linalg.norm(hi - lo) + np.linalg.norm(np.array(cam["eye"]) - centre))
    scene["camera"] = {
        "type": "perspective", "fov": cam["fov"], "fov_axis": "y",
        "near_clip": 1e-6 * extent, "far_clip": 10.0 * extent,
        "to_world": look_at(cam["eye"], cam["look"], cam["up"]),
        "film": {"type": "hdrfilm", "width": width or cfg.width, "height": height or cfg.height,
                 "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        "sampler": {"type": "stratified", "sample_count": spp, "seed": seed},
    }
    scene["integrator"] = {"type": "vkrt_whitted",
                           "max_depth": cfg.max_depth if max_depth is None else max_depth,
                           "ambient": ambient.tolist()}
    return scene


# ---- What Mitsuba has no plugin for ------------------------------------------------------------

class BlinnPhong(mi.BSDF):
    """vkrt's @phong: Kd/pi plus the normalised Blinn-Phong lobe Ks (Ns + 8) / (8 pi) cos^Ns of the
    half-vector angle, two-sided. Mitsuba 3 has no Phong model (Mitsuba 0.6's `phong` was the
    modified Phong of Lafortune and Willems, another lobe). Sampled by the cosine, which is only
    used for the ambient term's albedo (the integrator never continues from a smooth surface)."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.kd = props.get_texture("kd")
        self.ks = props.get_texture("ks")
        self.ns = float(props["ns"])
        flags = (mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.GlossyReflection |
                 mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide)
        self.m_flags = flags
        self.m_components = [flags]

    def eval(self, ctx, si, wo, active=True):
        # Two-sided: mirror both directions to the side the viewer is on.
        flip = mi.Frame3f.cos_theta(si.wi) < 0
        wi = mi.Vector3f(si.wi.x, si.wi.y, dr.select(flip, -si.wi.z, si.wi.z))
        wo = mi.Vector3f(wo.x, wo.y, dr.select(flip, -wo.z, wo.z))
        cos_o = mi.Frame3f.cos_theta(wo)
        h = dr.normalize(wi + wo)
        lobe = (self.ns + 8.0) / (8.0 * dr.pi) * dr.power(dr.maximum(h.z, 0.0), self.ns)
        f = self.kd.eval(si, active) * dr.inv_pi + self.ks.eval(si, active) * lobe
        return dr.select(active & (cos_o > 0) & (mi.Frame3f.cos_theta(wi) > 0), f * cos_o, 0.0)

    def pdf(self, ctx, si, wo, active=True):
        return dr.select(active, mi.warp.square_to_cosine_hemisphere_pdf(
            mi.Vector3f(wo.x, wo.y, dr.abs(wo.z))), 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

    def sample(self, ctx, si, sample1, sample2, active=True):
        bs = mi.BSDFSample3f()
        wo = mi.warp.square_to_cosine_hemisphere(sample2)
        bs.wo = dr.select(mi.Frame3f.cos_theta(si.wi) < 0, mi.Vector3f(wo.x, wo.y, -wo.z), wo)
        bs.pdf = mi.warp.square_to_cosine_hemisphere_pdf(wo)
        bs.eta = 1.0
        bs.sampled_type = mi.UInt32(+mi.BSDFFlags.DiffuseReflection)
        bs.sampled_component = mi.UInt32(0)
        value = self.eval(ctx, si, bs.wo, active) / dr.maximum(bs.pdf, 1e-12)
        return bs, dr.select(active & (bs.pdf > 0), value, 0.0)

    def eval_diffuse_reflectance(self, si, active=True):
        return self.kd.eval(si, active)

    def traverse(self, callback):
        pass

    def to_string(self):
        return f"BlinnPhong[ns={self.ns}]"


class Whitted(mi.SamplingIntegrator):
    """vkrt's light transport with Mitsuba's parts. At every hit: the emission of the surface
    (area emitters are only seen, never sampled: vkrt's emissive surfaces light nothing), the
    direct light of every delta light (point, spot, directional), each one sampled, shadow-tested
    and weighted by the BSDF (Mitsuba's), plus ambient x albedo (Mitsuba's
    eval_diffuse_reflectance), unshadowed. Then the path goes on only through delta (mirror,
    glass) and null (see-through) lobes, sampled by Mitsuba's BSDF; it ends at smooth surfaces,
    after max_depth bounces, or in the environment (the constant emitter, seen only by rays that
    leave the scene, as vkrt's environment is)."""

    def __init__(self, props):
        mi.SamplingIntegrator.__init__(self, props)
        self.max_depth = props.get("max_depth", 6)
        self.ambient = mi.Color3f(props.get("ambient", [0.0, 0.0, 0.0]))

    def sample(self, scene, sampler, ray, medium=None, active=True):
        ctx = mi.BSDFContext()
        ray = mi.Ray3f(ray)
        result = mi.Color3f(0.0)
        throughput = mi.Color3f(1.0)
        active = mi.Bool(active)
        lights = [e for e in scene.emitters()
                  if mi.has_flag(e.flags(), mi.EmitterFlags.Delta)]
        environment = scene.environment()
        for depth in range(self.max_depth + 1):
            si = scene.ray_intersect(ray, active)
            missed = active & ~si.is_valid()
            if environment is not None:
                result += dr.select(missed, throughput * environment.eval(si, missed), 0.0)
            active &= si.is_valid()
            result += dr.select(active, throughput * si.emitter(scene).eval(si, active), 0.0)
            bsdf = si.bsdf(ray)
            for light in lights:
                ds, radiance = light.sample_direction(si, sampler.next_2d(active), active)
                lit = active & (ds.pdf > 0)
                lit &= ~scene.ray_test(si.spawn_ray_to(ds.p), lit)
                f = bsdf.eval(ctx, si, si.to_local(ds.d), lit)
                result += dr.select(lit, throughput * f * radiance, 0.0)
            result += dr.select(active, throughput * self.ambient *
                                bsdf.eval_diffuse_reflectance(si, active), 0.0)
            if depth == self.max_depth:
                break
            bs, weight = bsdf.sample(ctx, si, sampler.next_1d(active), sampler.next_2d(active),
                                     active)
            specular = (mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta) |
                        mi.has_flag(bs.sampled_type, mi.BSDFFlags.Null))
            active &= specular & (bs.pdf > 0) & (dr.max(weight) > 0)
            throughput *= weight
            ray = si.spawn_ray(si.to_world(bs.wo))
        return result, mi.Bool(True), []

    def aov_names(self):
        return []

    def to_string(self):
        return f"VkrtWhitted[max_depth={self.max_depth}]"


mi.register_bsdf("vkrt_blinn_phong", lambda props: BlinnPhong(props))
mi.register_integrator("vkrt_whitted", lambda props: Whitted(props))

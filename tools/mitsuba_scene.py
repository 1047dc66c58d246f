"""mitsuba_scene: a vkrt scene (scene.cfg, its OBJ and .mtl) as a Mitsuba 3 scene, rendered with
the light transport vkrt models: Whitted's (an integrator written here) or the path tracer's
(Mitsuba's own `path`). Used by tools/reference.

Nothing here comes from vkrt's code: scene.cfg, OBJ and .mtl are read again, in Python, from
their documentation (docs/scene-format.md, docs/materials.md). Mitsuba traces the rays,
evaluates and samples the BSDFs (its diffuse, conductor and dielectric), the lights (its point,
spot, directional, area, constant and envmap emitters), the textures (its bitmap) and the
camera (its perspective sensor and box filter). What Mitsuba lacks is written here, small: the
Blinn-Phong BRDF, vkrt's two-sided convention (the side is the triangle's, not the interpolated
normal's) and its rule for normals bent by a normal or height map (Mitsuba's adapters treat one
bent away from the viewer otherwise), the unshadowed ambient light, the clear coat's layering
(vkrt_coat), the sum of a base and the sheen (vkrt_sheen; the sheen itself is Mitsuba's
`principled`), and the Whitted integrator that stops at the first diffuse surface. docs/speed-vs-accuracy.md lists what matches exactly and what cannot."""
import os

import numpy as np

import mitsuba as mi
import drjit as dr


class SceneError(Exception):
    """A scene this tool cannot read, or cannot express in Mitsuba."""


# vkrt's path tracer plays Russian roulette at the hits of rays of this depth and deeper (the
# camera ray is depth 0): glsl/lib/path.glsl's ROULETTE_DEPTH. Change both together.
VKRT_ROULETTE_DEPTH = 4
# Mitsuba's `path` counts path segments: max_depth M renders paths of at most M segments (1: only
# emitters seen directly, 2: direct light), and its next-event estimation stops one short so that
# both strategies cover the same paths. vkrt's `max-depth D` traces rays of depth 0 to D and takes
# direct light (a light sample) at the hit of every one, the last included: paths of up to D + 2
# segments (camera ray, D bounce rays, the light's segment), as in Whitted mode. Were vkrt to stop
# its next-event estimation at depth D - 1 instead, this would be 1.
PATH_SEGMENTS_PAST_MAX_DEPTH = 2


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
        self.environment_map = None  # (path, scale, rotate degrees)
        self.integrator = "auto"
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
            elif key == "environment-map":
                options = dict(zip(args[1::2], args[2::2]))
                if not args or set(options) - {"scale", "rotate"} or len(args) % 2 != 1:
                    raise SceneError(f"{where}: write environment-map FILE [scale S] [rotate DEG]")
                cfg.environment_map = (os.path.join(folder, args[0]),
                                       float(options.get("scale", 1.0)),
                                       float(options.get("rotate", 0.0)))
            elif key == "integrator":
                if args not in (["auto"], ["whitted"], ["path"]):
                    raise SceneError(f"{where}: integrator is auto, whitted or path")
                cfg.integrator = args[0]
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
                lens = dict(zip(args[fov_at + 2::2], args[fov_at + 3::2]))  # aperture, focus
                cfg.cameras.append({"eye": [float(x) for x in parts["eye"]],
                                    "look": [float(x) for x in parts["look"]],
                                    "up": [float(x) for x in parts["up"]],
                                    "fov": float(args[fov_at + 1]),
                                    "aperture": float(lens.get("aperture", 0)),
                                    "focus": float(lens.get("focus", 0))})
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
        self.roughness = 0.0  # a material file's number 16 (the rough built-ins)
        self.coat, self.coat_roughness = 0.0, 0.0  # numbers 18 and 19: the clear coat
        self.sheen = 0.0  # number 20: the sheen's weight (the .mtl's Ps)
        # The maps that change the surface (docs/materials.md, "Normal, bump and emission maps"):
        # `norm`, `map_Bump`/`bump` with the -bm of the statement that names the map used, and
        # map_Ke; ke_given: without a Ke line a map_Ke is the emission itself (Ke 1 1 1).
        self.norm = self.map_bump = self.map_ke = None
        self.norm_bm = self.bump_bm = 1.0
        self.ke_given = False

    def detail_map(self):
        """(path, kind, -bm) of the map that bends the normal, kind "normal" or "height", or
        None: `norm` wins over map_Bump, and a map_Bump whose image reads as a normal map is one
        (vkrt's test, looks_like_normal_map)."""
        if self.norm:
            return self.norm, "normal", self.norm_bm
        if self.map_bump:
            kind = "normal" if looks_like_normal_map(self.map_bump) else "height"
            return self.map_bump, kind, self.bump_bm
        return None

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
                m.ke_given |= key == "Ke"
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
            elif key == "norm":
                m.norm, m.norm_bm = find_file(folder, args[-1]), bump_multiplier(args)
            elif key in ("map_Bump", "map_bump", "bump"):  # the last statement wins, as in vkrt
                m.map_bump, m.bump_bm = find_file(folder, args[-1]), bump_multiplier(args)
            elif key == "map_Ke":
                m.map_ke = find_file(folder, args[-1])
    for m in materials.values():
        if m.map_ke and not m.ke_given:
            m.ke = [1.0, 1.0, 1.0]


def bump_multiplier(args):
    """A map statement's `-bm S` (1 without one); the file name is its last word."""
    for i, word in enumerate(args[:-2]):
        if word == "-bm":
            return float(args[i + 1])
    return 1.0


BUILTINS = ("diffuse", "textured", "phong", "mirror", "glass", "emissive", "roughconductor",
            "roughdielectric", "roughplastic")


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
            p = [float(x) for x in w[3 + count:]] + [0.0] * 21
            m = Material(name, folder)
            m.shader = shader[1:] if shader.startswith("@") else os.path.join(folder, shader)
            m.where = f"{path}:{number}"
            m.kd, m.d, m.ks, m.ns, m.ke = p[0:3], 1.0 - p[3], p[4:7], p[7], p[8:11]
            m.ni, m.tf = p[11], p[12:15]
            m.roughness = p[16]
            m.coat, m.coat_roughness = min(max(p[18], 0.0), 1.0), p[19]
            m.sheen = min(max(p[20], 0.0), 1.0)
            m.map_kd = textures[0] if textures else None
            m.map_d = textures[1] if len(textures) > 1 else None
            out[name] = m
    return out


def read_obj(path):
    """The triangles of an OBJ, grouped by material: {material name: {"p": [n, 3, 3] positions,
    "n": [n, 3, 3] normals or None, "has_n": per triangle, whether all its corners have one,
    "uv": [n, 3, 2]}}, and the .mtl materials. Polygons become triangle fans, as in vkrt.
    Corners without `vt` get uv (0, 0), vkrt's convention (docs/scene-format.md): Mitsuba would
    otherwise use the hit's barycentric coordinates as uv. Vertex normals are turned to the side
    of their triangle's own (counter-clockwise) normal, as vkrt turns the interpolated one."""
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
    v, vn = np.array(v, np.float64), np.array(vn, np.float64)
    vt = np.array(vt + [[0.0, 0.0]], np.float64)  # the last row: uv (0, 0) for corners without

    out = {}
    for name, tris in groups.items():
        idx = np.array(tris, np.int64)  # [n, 3 corners, (v, vt, vn)], -1: absent
        p = v[idx[:, :, 0]]
        with_n = (idx[:, :, 2] >= 0).all(axis=1) if len(vn) else np.zeros(len(idx), bool)
        n = None
        if len(vn):
            n = vn[np.where(idx[:, :, 2] >= 0, idx[:, :, 2], 0)]
            face = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
            n = np.where((n * face[:, None, :]).sum(axis=-1, keepdims=True) < 0, -n, n)
        out[name] = {"p": p, "uv": vt[idx[:, :, 1]], "n": n, "has_n": with_n}
    return out, materials


# ---- Mitsuba objects ---------------------------------------------------------------------------

def rgb(value):
    return {"type": "rgb", "value": [float(x) for x in value]}


def luminance(c):
    """Relative luminance of linear Rec. 709 RGB (the weights vkrt gives lobes and lights)."""
    return float(np.dot(np.asarray(c, np.float64), [0.2126, 0.7152, 0.0722]))


def reflectance(value):
    """A constant colour as a Mitsuba texture. Mitsuba's `rgb` refuses reflectances outside
    [0, 1] ("Invalid RGB reflectance value"); vkrt accepts any Kd, Ks or Tf that is not negative,
    so a colour above 1 becomes a 1x1 raw bitmap, which Mitsuba takes as it is."""
    value = np.asarray(value, np.float64)
    if (value <= 1.0).all():
        return rgb(value)
    return {"type": "bitmap", "bitmap": mi.Bitmap(value.reshape(1, 1, 3).astype(np.float32)),
            "raw": True, "filter_type": "nearest"}


def texture_times(path, factor):
    """Mitsuba's bitmap texture of an sRGB image decoded to linear by Mitsuba (per texel, before
    filtering, as vkrt does), times factor (Kd); bilinear, repeating."""
    bitmap = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32,
                                     srgb_gamma=False)
    texels = np.array(bitmap) * np.array(factor, np.float32)
    return {"type": "bitmap", "bitmap": mi.Bitmap(texels.astype(np.float32)), "raw": True,
            "filter_type": "bilinear", "wrap_mode": "repeat"}


def coverage_texture(path):
    """A map_d as vkrt reads it (src/scene/texture.c): its alpha channel when it has one that is
    not opaque everywhere, else its first channel, raw (no sRGB decoding)."""
    import numpy as np
    source = mi.Bitmap(path)
    source.set_srgb_gamma(False)  # coverage is stored as is: no sRGB decoding
    channels = np.array(source.convert(srgb_gamma=False, component_format=mi.Struct.Type.Float32))
    if channels.ndim == 2:
        channels = channels[..., None]
    has_alpha = source.pixel_format() in (mi.Bitmap.PixelFormat.YA, mi.Bitmap.PixelFormat.RGBA)
    use = channels[..., -1] if has_alpha and (channels[..., -1] < 1.0).any() else channels[..., 0]
    bitmap = mi.Bitmap(np.ascontiguousarray(use[..., None], dtype=np.float32))
    return {"type": "bitmap", "bitmap": bitmap, "raw": True, "filter_type": "bilinear",
            "wrap_mode": "repeat"}


def data_texels(path):
    """An image's texels as stored (8-bit as /255, no sRGB decoding): how vkrt reads normal and
    height maps. [h, w, 3] float32, the top row first; a grey image as three equal channels."""
    source = mi.Bitmap(path)
    source.set_srgb_gamma(False)
    return np.array(source.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32,
                                   srgb_gamma=False), np.float32)


def looks_like_normal_map(path):
    """vkrt's test of a map_Bump image (src/scene/texture.c, vkrt_texture_is_normal_map): a
    tangent-space normal map averages to about (0.5, 0.5, 1), red and green within 0.25 of 0.5,
    blue above 0.8 and 0.2 above both; a grey or colour height map does not."""
    r, g, b = data_texels(path).reshape(-1, 3).mean(axis=0, dtype=np.float64)
    return abs(r - 0.5) < 0.25 and abs(g - 0.5) < 0.25 and b > 0.8 and b > max(r, g) + 0.2


def data_texture(texels):
    return {"type": "bitmap", "bitmap": mi.Bitmap(np.ascontiguousarray(texels, np.float32)),
            "raw": True, "filter_type": "bilinear", "wrap_mode": "repeat"}


def surface_map(path, kind, multiplier, mirrored):
    """The properties that make vkrt_twosided bend its normal by a normal or height map (its
    _mapped_normal says how), or for smooth glass, which is not wrapped in it, Mitsuba's own
    adapter (`bumpmap`, `normalmap`) as a dict without its nested "bsdf".
    Height map: the mean of the channels (vkrt's height; Mitsuba's bumpmap would read the
    luminance), times -bm. Normal map: -bm scales x and y, which is linear in the texel, so it is
    baked into the texels; so is vkrt's mirroring of the bitangent on triangles whose uv are
    mirrored (green inverted): the frame built from Mitsuba's dp/du has t = n x s always."""
    texels = data_texels(path)
    if kind == "height":
        return {"height": data_texture(texels.mean(axis=2, keepdims=True)),
                "bump_scale": float(multiplier)}
    xy = 2.0 * texels[..., :2] - 1.0
    xy *= np.float32(multiplier)
    if mirrored:
        xy[..., 1] = -xy[..., 1]
    texels[..., :2] = 0.5 * (xy + 1.0)
    return {"normal_map": data_texture(texels)}


def with_surface_map(bsdf, mapping):
    """bsdf with a surface_map: given to vkrt_twosided (inside a mask, if any), which maps on the
    front side and turns the result to the viewer's side as vkrt does. Smooth glass, two-sided
    already and not wrapped, gets Mitsuba's adapter around it (with its own rules for normals
    that face away, and its shadow terminator term off)."""
    if bsdf["type"] == "mask":
        return {**bsdf, "bsdf": with_surface_map(bsdf["bsdf"], mapping)}
    if bsdf["type"] == "vkrt_twosided":
        return {**bsdf, **mapping}
    if "height" in mapping:
        adapter = {"type": "bumpmap", "texture": mapping["height"],
                   "scale": mapping["bump_scale"]}
    else:
        adapter = {"type": "normalmap", "normalmap": mapping["normal_map"]}
    return {**adapter, "use_shadowing_function": False, "bsdf": bsdf}


def uv_orientation(tris):
    """Per triangle: +1 where its uv keep the winding, -1 where they mirror it, 0 where they are
    degenerate (on a line, or none: vkrt keeps the normal there). The sign of the uv determinant
    is that of (dp/du x dp/dv) . (the counter-clockwise normal)."""
    uv = tris["uv"]
    d1, d2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    det = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    return np.sign(det).astype(np.int64)


def two_sided(bsdf, reads_wi=False):
    """vkrt's two-sided surface around a one-sided BSDF (VkrtTwoSided, below)."""
    return {"type": "vkrt_twosided", "bsdf": bsdf, "reads_wi": reads_wi}


def rough_bsdf(m, kind, albedo, notes):
    """Mitsuba's GGX BSDFs for vkrt's rough built-ins (glsl/lib/microfacet.glsl): the same
    distribution, separable Smith masking and visible-normal sampling, alpha = roughness^2 (vkrt's
    number is Blender's perceptual roughness, Mitsuba's `alpha` the GGX parameter). Where the
    models differ, a note says so."""
    if kind == "roughplastic" and m.ni == 1.0 and not any(m.ks):
        # A plastic of index 1 has no coat of its own (Fresnel 0 both ways) and, with Ks 0, no
        # specular lobe: vkrt's plastic is then exactly Lambertian.
        return two_sided(coated(m, sheened(m, {"type": "diffuse", "reflectance": albedo})))
    r = min(max(m.roughness, 0.0), 1.0)
    ggx = {"distribution": "ggx", "alpha": max(r * r, 1e-4), "sample_visible": True}
    plastic = {"int_ior": m.ni if m.ni > 0 else 1.5, "ext_ior": 1.0,
               "diffuse_reflectance": albedo, "nonlinear": False,
               "specular_reflectance": reflectance(m.ks)}
    if kind == "roughplastic" and r < 0.02:
        # vkrt's smooth coat is Mitsuba's smooth `plastic` (its base under the smooth Fresnel);
        # Mitsuba's roughplastic does not tend to it (its internal reflectance is a mean over 64
        # cosines: 0.981 at cos 0.5 for Kd 1, Ni 1.5 and roughness 0.01, `plastic` 1.001).
        return two_sided(coated(m, sheened(m, {"type": "plastic", **plastic})))
    if r < 0.02:
        notes.append(f"material '{m.name}': roughness {r} is smooth in vkrt (a delta lobe); "
                     "Mitsuba gets GGX of alpha 1e-4")
    if kind == "roughconductor":
        # vkrt's Fresnel is Schlick's with F0 = Ks; Mitsuba's conductor `none` is Ks at every
        # angle: the same where Ks is 1, brighter towards grazing angles in vkrt otherwise.
        if min(m.ks) < 1.0:
            notes.append(f"material '{m.name}': vkrt's Schlick Fresnel of Ks {m.ks} rises to 1 at "
                         "grazing angles; Mitsuba's conductor `none` stays at Ks")
        return two_sided(coated(m, {"type": "roughconductor", "material": "none",
                                    "specular_reflectance": reflectance(m.ks), **ggx}))
    if kind == "roughdielectric":
        tint = m.tf if any(m.tf) else [1.0, 1.0, 1.0]
        return coated(m, {"type": "roughdielectric", "int_ior": m.ni if m.ni > 0 else 1.5,
                          "ext_ior": 1.0, "specular_transmittance": reflectance(tint), **ggx})
    # vkrt's @roughplastic is Mitsuba's roughplastic, its coat tables made the same way.
    return two_sided(coated(m, sheened(m, {"type": "roughplastic", **plastic, **ggx})))


def sheened(m, base):
    """The base with the material's sheen (number 20; Sheen, below) beside it, or the base alone
    where it has none. Only the plastic has one in vkrt (the conductor and glass have none)."""
    if m.sheen <= 0.0:
        return base
    return {"type": "vkrt_sheen", "base": base, "weight": m.sheen}


def coated(m, base):
    """The base under the material's clear coat (numbers 18, 19; ClearCoat, below), or the base
    alone where it has none."""
    if m.coat <= 0.0:
        return base
    r = min(max(m.coat_roughness, 0.0), 1.0)
    return {"type": "vkrt_coat", "base": base, "weight": m.coat, "alpha": max(r * r, 1e-4)}


def bsdf_for(m, notes):
    """The Mitsuba BSDF of a material, mapped as vkrt maps it. vkrt's surfaces are two-sided, so
    the one-sided Mitsuba BSDFs are wrapped in vkrt_twosided (glass is two-sided already).
    What is worth a warning (a material that reflects more than it receives) goes to notes."""
    kind = m.builtin()
    if kind not in BUILTINS:
        raise SceneError(f"{getattr(m, 'where', m.name)}: material '{m.name}' uses shader "
                         f"{kind}, which has no Mitsuba counterpart")
    # @diffuse reads no texture; the others multiply Kd by map_Kd (mtl_diffuse).
    textured = m.map_kd and kind != "diffuse"
    albedo = texture_times(m.map_kd, m.kd) if textured else reflectance(m.kd)
    if kind in ("diffuse", "textured", "emissive"):
        bsdf = two_sided({"type": "diffuse", "reflectance": rgb([0, 0, 0]) if kind == "emissive"
                          else albedo})
    elif kind == "phong":
        bsdf = two_sided({"type": "vkrt_blinn_phong", "kd": albedo, "ks": reflectance(m.ks),
                          "ns": m.ns}, reads_wi=True)
    elif kind == "mirror":
        mirror = {"type": "conductor", "material": "none", "specular_reflectance":
                  reflectance(m.ks)}
        w = luminance(m.ks) / (luminance(m.kd) + luminance(m.ks)) if any(m.ks) else 0.0
        if not any(m.kd) and not m.map_kd:
            bsdf = two_sided(mirror)
        elif w == 0.0:
            bsdf = two_sided({"type": "diffuse", "reflectance": albedo})
        else:
            # vkrt's mirror is Kd/pi plus a perfect mirror of Ks: their sum. blendbsdf gives
            # (1 - w) bsdf_0 + w bsdf_1 and samples bsdf_1 with probability w, so each lobe is
            # scaled by the inverse of its weight; w = Ks's share of the luminance, the
            # probability with which vkrt's path tracer picks the mirror.
            base = np.asarray(m.kd) / (1.0 - w)
            diffuse = {"type": "diffuse", "reflectance": texture_times(m.map_kd, base)
                       if m.map_kd else reflectance(base)}
            mirror["specular_reflectance"] = reflectance(np.asarray(m.ks) / w)
            bsdf = two_sided({"type": "blendbsdf", "weight": w, "bsdf_0": diffuse,
                              "bsdf_1": mirror})
        if (np.asarray(m.kd) + np.asarray(m.ks)).max() > 1.0:
            notes.append(f"material '{m.name}': Kd + Ks = "
                         f"{np.round(np.asarray(m.kd) + np.asarray(m.ks), 3).tolist()} is more "
                         "than 1, so it reflects more light than it receives; rendered as vkrt "
                         "renders it (the sum of both lobes), which is not physical")
    elif kind in ("roughconductor", "roughdielectric", "roughplastic"):
        bsdf = rough_bsdf(m, kind, albedo, notes)
    elif kind == "glass":
        tint = m.tf if any(m.tf) else [1.0, 1.0, 1.0]
        bsdf = {"type": "dielectric", "int_ior": m.ni if m.ni > 0 else 1.5, "ext_ior": 1.0,
                "specular_transmittance": reflectance(tint)}
    if kind in ("diffuse", "textured", "phong") and (m.d < 1.0 or m.map_d):
        opacity = coverage_texture(m.map_d) if m.map_d else m.d
        if m.map_d and m.d < 1.0:
            raise SceneError(f"material '{m.name}': d < 1 together with map_d is not mapped")
        bsdf = {"type": "mask", "opacity": opacity, "bsdf": bsdf}
    return bsdf


def mesh_for(name, tris, with_normals, bsdf, emission):
    """A Mitsuba mesh of triangles [n, 3, 3] with per-corner normals and uvs (corners are not
    shared: OBJ indexes positions, uvs and normals separately). An emission makes it an `area`
    emitter, which emits from its front only (Mitsuba decides by the shading normal, which
    read_obj turned to the counter-clockwise side)."""
    count = len(tris["p"])
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    if emission is not None:
        props["emitter"] = mi.load_dict({"type": "area", "radiance": emission})
    mesh = mi.Mesh(name, 3 * count, count, props=props, has_vertex_normals=with_normals,
                   has_vertex_texcoords=True)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(tris["p"].astype(np.float32).ravel())
    params["faces"] = mi.UInt32(np.arange(3 * count, dtype=np.uint32))
    if with_normals:
        params["vertex_normals"] = mi.Float(tris["n"].astype(np.float32).ravel())
    uv = tris["uv"].astype(np.float32).copy()
    uv[:, :, 1] = 1.0 - uv[:, :, 1]  # OBJ's v grows upwards, Mitsuba's bitmap rows downwards
    params["vertex_texcoords"] = mi.Float(uv.ravel())
    params.update()
    return mesh


def environment_map(path, scale, rotate):
    """Mitsuba's `envmap` of an equirectangular image, read as vkrt reads it (src/scene/envmap.h):
    8-bit images decoded from sRGB, channels below 0 or NaN as 0, above 65504 (half float) as
    65504. The two conventions are the same: Mitsuba sees pixel column u (0 at the left) in the
    direction (sin phi sin theta, cos theta, -cos phi sin theta), phi = 2 pi u, theta from +y (the
    top row); the left edge looks down -z, a quarter across down +x. vkrt's `rotate DEG` turns
    the map about +y, Mitsuba's to_world = rotate([0, 1, 0], DEG)."""
    if not os.path.exists(path):
        raise SceneError(f"environment-map '{path}': no such file")
    bitmap = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32,
                                     srgb_gamma=False)
    texels = np.nan_to_num(np.array(bitmap), nan=0.0, posinf=65504.0)
    texels = np.clip(texels, 0.0, 65504.0).astype(np.float32)
    return {"type": "envmap", "bitmap": mi.Bitmap(texels), "scale": float(scale),
            "to_world": mi.ScalarTransform4f().rotate([0.0, 1.0, 0.0], float(rotate))}


def look_at(origin, target, up):
    return mi.ScalarTransform4f().look_at(origin=mi.ScalarPoint3f(origin),
                                          target=mi.ScalarPoint3f(target),
                                          up=mi.ScalarVector3f(up))


def any_perpendicular(d):
    d = np.array(d, np.float64) / np.linalg.norm(d)
    a = [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0]
    return np.cross(d, a).tolist()


def choose_integrator(requested, emissive, environment_map):
    """The integrator for `integrator auto|whitted|path` and the reason: auto takes path when the
    scene has light that only a path tracer carries (an emissive material some triangle uses,
    or an environment map), else whitted."""
    if requested != "auto":
        return requested, "asked for"
    if emissive:
        return "path", f"auto: emissive material '{emissive}'"
    if environment_map:
        return "path", "auto: an environment map"
    return "whitted", "auto: only point, spot, directional and ambient lights"


def scene_dict(cfg, frame=0, width=None, height=None, spp=64, seed=0, max_depth=None,
               integrator=None, notes=None):
    """The Mitsuba scene dict of a vkrt scene's frame, the integrator chosen ("whitted" or
    "path", from `integrator` or else the scene.cfg's) and the reason. Warnings go to notes."""
    notes = [] if notes is None else notes
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
    used = {name: materials.get(name, DEFAULT_MATERIAL) if name is not None
            else DEFAULT_MATERIAL for name in groups}
    emissive = next((m.name for m in used.values() if any(x > 0 for x in m.ke)), None)
    chosen, reason = choose_integrator(integrator or cfg.integrator, emissive,
                                       cfg.environment_map)
    scene = {"type": "scene"}
    lo = np.min([g["p"].reshape(-1, 3).min(axis=0) for g in groups.values()], axis=0)
    hi = np.max([g["p"].reshape(-1, 3).max(axis=0) for g in groups.values()], axis=0)
    for i, (name, tris) in enumerate(groups.items()):
        m = used[name]
        bsdf = bsdf_for(m, notes)
        # map_Ke: Mitsuba's area emitter takes a texture as its radiance (Ke x the map, decoded
        # from sRGB as map_Kd); it draws points by area, vkrt by the map's mean: the same light.
        emission = None
        if any(m.ke):
            emission = texture_times(m.map_ke, m.ke) if m.map_ke else rgb(m.ke)
        # Triangles whose uv are degenerate keep their normal in vkrt; mirrored ones mirror a
        # normal map's bitangent: each kind is its own mesh, with its own adapter.
        detail = m.detail_map()
        orientation = (uv_orientation(tris) if detail else np.zeros(len(tris["p"]), np.int64))
        if detail and detail[1] == "height":
            orientation = np.abs(orientation)  # a height map has no bitangent to mirror
        bsdfs = {0: bsdf}
        for o in set(orientation.tolist()) - {0}:
            bsdfs[o] = with_surface_map(bsdf, surface_map(*detail, mirrored=o < 0))
        has_n = tris["has_n"]
        for with_normals in (True, False):
            for o, part_bsdf in bsdfs.items():
                pick = (has_n if with_normals else ~has_n) & (orientation == o)
                if not pick.any():
                    continue
                part = {"p": tris["p"][pick], "uv": tris["uv"][pick],
                        "n": None if tris["n"] is None else tris["n"][pick]}
                scene[f"mesh{i}_{int(with_normals)}_{o + 1}"] = mesh_for(
                    f"{name}", part, with_normals, part_bsdf, emission)
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
    if cfg.environment_map:
        scene["environment"] = environment_map(*cfg.environment_map)
    elif any(environment):
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
    if cam["aperture"] > 0:
        # vkrt's thin lens (raygen.comp) is Mitsuba's thinlens: the lens radius, and the
        # distance in focus along the view axis (|look - eye| when not given).
        focus = cam["focus"] or float(np.linalg.norm(np.array(cam["look"]) - np.array(cam["eye"])))
        scene["camera"].update({"type": "thinlens", "aperture_radius": cam["aperture"],
                                "focus_distance": focus})
    depth = cfg.max_depth if max_depth is None else max_depth
    if chosen == "path":
        if ambient.any():
            notes.append("ambient light is left out in path mode: it stands in for the indirect "
                         "light, which the path tracer computes (as vkrt's path tracer does)")
        scene["integrator"] = {"type": "path", "max_depth": depth + PATH_SEGMENTS_PAST_MAX_DEPTH,
                               "rr_depth": VKRT_ROULETTE_DEPTH + 1, "hide_emitters": False}
    else:
        scene["integrator"] = {"type": "vkrt_whitted", "max_depth": depth,
                               "ambient": ambient.tolist()}
    return scene, chosen, reason


# ---- What Mitsuba has no plugin for ------------------------------------------------------------

def _flip_z(v, flip):
    return mi.Vector3f(v.x, v.y, dr.select(flip, -v.z, v.z))


class VkrtTwoSided(mi.BSDF):
    """vkrt's two-sided surface (docs/materials.md, `Surface`): the geometric normal is turned to
    the side the ray comes from, and the interpolated (shading) normal to the geometric normal's
    side, as pbrt does; light counts only when it is in front of both. Mitsuba's `twosided`
    instead decides the side by the shading normal alone, so where bent vertex normals tilt the
    shading normal away from the viewer (near silhouettes of foliage and car bodies) it shows the
    back of the surface, and it lets light through the geometric surface by way of a bent
    normal. Here the nested one-sided BSDF sees wi and wo mirrored (z negated in the shading
    frame) when the shading normal must be turned, as Mitsuba's twosided mirrors them. A viewer
    that is then still below the shading normal, which vkrt's Lambertian lobe ignores, is moved
    onto it for Mitsuba's BSDFs (which would return nothing); the Blinn-Phong BSDF (reads_wi)
    reads the true direction, as vkrt's does.

    With a normal map (`normal_map`) or a height map (`height`, `bump_scale`) the nested BSDF
    sees the mapped normal instead (_mapped_normal), turned to the viewer's side and kept in
    front of the geometric normal and the viewer as vkrt keeps it."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.nested = props["bsdf"]
        self.reads_wi = bool(props.get("reads_wi", False))
        self.normal_map = props["normal_map"] if props.has_property("normal_map") else None
        self.height = props["height"] if props.has_property("height") else None
        self.bump_scale = float(props.get("bump_scale", 1.0))
        sides = mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
        self.m_components = [self.nested.flags(i) | sides
                             for i in range(self.nested.component_count())]
        self.m_flags = self.nested.flags() | sides

    def _mapped_normal(self, si, active):
        """The map's normal on the front side (that of si.sh_frame.n, the OBJ's normal turned
        to the counter-clockwise side by read_obj, or the winding's), in world space, from
        Mitsuba's texture lookups and dp/du, dp/dv (of its uv, whose v is the OBJ's flipped:
        both flips cancel in the normal). Normal map: (2 rgb - 1) in (s, t, n), s = dp/du made
        orthogonal to n, t = n x s (+v of the OBJ: green up, the OpenGL convention). Height map:
        the surface displaced by bump_scale x height along n, n' = (dp/du + dh/du n) x (dp/dv +
        dh/dv n) with dp/du, dp/dv made orthogonal to n (Mitsuba's bumpmap's frame), turned to
        n's side; dh/du and dh/dv by _height_slope."""
        n = si.sh_frame.n
        su = dr.normalize(si.dp_du - n * dr.dot(n, si.dp_du))
        if self.normal_map is not None:
            c = self.normal_map.eval(si, active) * 2.0 - 1.0
            m = su * c.x + dr.cross(n, su) * c.y + n * c.z
        else:
            g = self.bump_scale * self._height_slope(si, active)
            du = si.dp_du + n * (g.x - dr.dot(n, si.dp_du))
            dv = si.dp_dv + n * (g.y - dr.dot(n, si.dp_dv))
            m = dr.cross(du, dv)
            m = dr.select(dr.dot(m, n) < 0, -m, m)
        length = dr.norm(m)
        ok = (length > 0) & dr.isfinite(length)
        return dr.select(ok, m / dr.select(ok, length, 1.0), n)

    def _height_slope(self, si, active):
        """(dh/du, dh/dv) as vkrt takes them: central differences of the bilinear lookups half a
        texel either side (the slope of a ramp exactly). Mitsuba's bumpmap takes the bitmap's
        eval_1_grad, the derivative of the bilinear interpolant, which differs where the slope
        changes inside a texel: with it Sponza read +0.16% brighter in the mean (research/
        journal.md, "Surface maps in the reference")."""
        size = mi.Vector2f(self.height.resolution())

        def h(du, dv):
            at = mi.SurfaceInteraction3f(si)
            at.uv = si.uv + mi.Vector2f(du, dv)
            return self.height.eval_1(at, active)

        return mi.Vector2f((h(0.5 / size.x, 0.0) - h(-0.5 / size.x, 0.0)) * size.x,
                           (h(0.0, 0.5 / size.y) - h(0.0, -0.5 / size.y)) * size.y)

    def _sides(self, si, active=True):
        """(to_inner, to_outer, viewer's side of the geometric normal, the geometric normal, the
        nested si): directions in si's frame to the nested BSDF's frame and back."""
        ng = si.to_local(si.n)
        side = dr.dot(si.wi, ng)
        flip = side * ng.z < 0
        inner = mi.SurfaceInteraction3f(si)
        if self.normal_map is None and self.height is None:
            wi = _flip_z(si.wi, flip)
            if not self.reads_wi:
                wi = dr.normalize(mi.Vector3f(wi.x, wi.y, dr.maximum(wi.z, 1e-4)))
            inner.wi = wi
            return (lambda v: _flip_z(v, flip)), (lambda v: _flip_z(v, flip)), side, ng, inner
        # vkrt (glsl/lib/surface.glsl): the map's normal on the front side, turned to the
        # viewer's, then kept at least a cosine of 0.01 in front of the geometric normal and
        # then of the viewer (guard_mapped_normal, surface_maps.glsl).
        wi = si.to_world(si.wi)
        facing = dr.select(dr.dot(wi, si.n) < 0, -1.0, 1.0)
        n_g = si.n * facing
        n = self._mapped_normal(si, active) * facing
        for towards in (n_g, wi):
            c = dr.dot(n, towards)
            n = dr.select(c < 0.01, dr.normalize(n + (0.01 - c) * towards), n)
        inner.sh_frame = mi.Frame3f(n)
        inner.wi = inner.to_local(wi)
        return ((lambda v: inner.to_local(si.to_world(v))),
                (lambda v: si.to_local(inner.to_world(v))), side, ng, inner)

    def eval(self, ctx, si, wo, active=True):
        to_inner, _, side, ng, inner = self._sides(si, active)
        ok = active & (dr.dot(wo, ng) * side > 0)
        return dr.select(ok, self.nested.eval(ctx, inner, to_inner(wo), ok), 0.0)

    def pdf(self, ctx, si, wo, active=True):
        to_inner, _, side, ng, inner = self._sides(si, active)
        ok = active & (dr.dot(wo, ng) * side > 0)
        return dr.select(ok, self.nested.pdf(ctx, inner, to_inner(wo), ok), 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        to_inner, _, side, ng, inner = self._sides(si, active)
        ok = active & (dr.dot(wo, ng) * side > 0)
        f, pdf = self.nested.eval_pdf(ctx, inner, to_inner(wo), ok)
        return dr.select(ok, f, 0.0), dr.select(ok, pdf, 0.0)

    def sample(self, ctx, si, sample1, sample2, active=True):
        _, to_outer, side, ng, inner = self._sides(si, active)
        bs, weight = self.nested.sample(ctx, inner, sample1, sample2, active)
        bs.wo = to_outer(bs.wo)
        # vkrt ends a path whose sampled direction would go through the geometric surface.
        ok = active & (dr.dot(bs.wo, ng) * side > 0)
        bs.pdf = dr.select(ok, bs.pdf, 0.0)
        return bs, dr.select(ok, weight, 0.0)

    def eval_diffuse_reflectance(self, si, active=True):
        return self.nested.eval_diffuse_reflectance(self._sides(si, active)[4], active)

    def traverse(self, callback):
        pass

    def to_string(self):
        return f"VkrtTwoSided[{self.nested}]"


class BlinnPhong(mi.BSDF):
    """vkrt's @phong, one-sided (VkrtTwoSided makes it two-sided): Kd/pi plus the normalised
    Blinn-Phong lobe Ks (Ns + 8) / (8 pi) cos^Ns of the half-vector angle. Mitsuba 3 has no Phong
    model (Mitsuba 0.6's `phong` was the modified Phong of Lafortune and Willems, another lobe).
    A proper BSDF for the path tracer: sampled as a mixture of the cosine lobe and the
    half-vector lobe (density (Ns + 1) / (2 pi) cos^Ns per half-vector, / (4 wo.h) per
    direction), chosen in proportion to the luminance of Kd and Ks, with the mixture's pdf (for
    MIS), as vkrt's glsl/materials/phong.glsl samples it. The value does not depend on the viewer
    being above the surface (vkrt's does not): only wo must be."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.kd = props.get_texture("kd")
        self.ks = props.get_texture("ks")
        self.ns = float(props["ns"])
        flags = (mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.GlossyReflection |
                 mi.BSDFFlags.FrontSide)
        self.m_flags = flags
        self.m_components = [flags]

    def _specular_probability(self, si, active):
        d = mi.luminance(self.kd.eval(si, active))
        k = mi.luminance(self.ks.eval(si, active))
        return dr.select(d + k > 0, k / (d + k), 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        cos_o = mi.Frame3f.cos_theta(wo)
        h = dr.normalize(si.wi + wo)
        lobe = dr.power(dr.maximum(h.z, 0.0), self.ns)
        f = (self.kd.eval(si, active) * dr.inv_pi +
             self.ks.eval(si, active) * ((self.ns + 8.0) / (8.0 * dr.pi) * lobe))
        ps = self._specular_probability(si, active)
        pdf = ((1.0 - ps) * cos_o * dr.inv_pi +
               ps * (self.ns + 1.0) / (2.0 * dr.pi) * lobe / (4.0 * dr.maximum(dr.dot(wo, h),
                                                                              1e-8)))
        ok = active & (cos_o > 0)
        return dr.select(ok, f * cos_o, 0.0), dr.select(ok, pdf, 0.0)

    def eval(self, ctx, si, wo, active=True):
        return self.eval_pdf(ctx, si, wo, active)[0]

    def pdf(self, ctx, si, wo, active=True):
        return self.eval_pdf(ctx, si, wo, active)[1]

    def sample(self, ctx, si, sample1, sample2, active=True):
        specular = sample1 < self._specular_probability(si, active)
        cos_h = dr.power(sample2.x, 1.0 / (self.ns + 1.0))
        sin_h = dr.safe_sqrt(1.0 - cos_h * cos_h)
        phi = 2.0 * dr.pi * sample2.y
        h = mi.Vector3f(sin_h * dr.cos(phi), sin_h * dr.sin(phi), cos_h)
        reflected = 2.0 * dr.dot(si.wi, h) * h - si.wi
        bs = mi.BSDFSample3f()
        bs.wo = dr.select(specular, reflected, mi.warp.square_to_cosine_hemisphere(sample2))
        f, bs.pdf = self.eval_pdf(ctx, si, bs.wo, active)
        bs.eta = 1.0
        bs.sampled_type = dr.select(specular, mi.UInt32(+mi.BSDFFlags.GlossyReflection),
                                    mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
        bs.sampled_component = mi.UInt32(0)
        ok = active & (bs.pdf > 0)
        return bs, dr.select(ok, f / dr.maximum(bs.pdf, 1e-20), 0.0)

    def eval_diffuse_reflectance(self, si, active=True):
        return self.kd.eval(si, active)

    def traverse(self, callback):
        pass

    def to_string(self):
        return f"BlinnPhong[ns={self.ns}]"


class Sheen(mi.BSDF):
    """vkrt's sheen (docs/materials.md, "The sheen") beside a nested Mitsuba BSDF: the sheen is
    Mitsuba's own `principled` BSDF's, evaluated by it, with base_color 0 (no diffuse, no
    retro-reflection) and specular 0 (index 1: no specular lobe), so that what it returns is its
    sheen term alone, sheen x (1 - |wo.h|)^5 x cos; vkrt's formula is not written here. Sampled
    as a mixture: the base's own sampling with probability 1/2, else the cosine hemisphere (as
    Mitsuba's principled samples its sheen); the pdf is the mixture's."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.base = props["base"]
        self.weight = float(props["weight"])
        self.sheen = mi.load_dict({"type": "principled", "base_color": {"type": "rgb",
                                                                         "value": [0.0, 0.0, 0.0]},
                                   "specular": 0.0, "metallic": 0.0, "sheen": self.weight})
        self.m_components = [self.base.flags(i) for i in range(self.base.component_count())] + [
            mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide]
        self.m_flags = self.base.flags() | mi.BSDFFlags.DiffuseReflection

    def eval_pdf(self, ctx, si, wo, active=True):
        fb, pb = self.base.eval_pdf(ctx, si, wo, active)
        ok = active & (mi.Frame3f.cos_theta(si.wi) > 0) & (mi.Frame3f.cos_theta(wo) > 0)
        fs = dr.select(ok, self.sheen.eval(ctx, si, wo, ok), 0.0)
        pc = dr.select(ok, mi.warp.square_to_cosine_hemisphere_pdf(wo), 0.0)
        return fb + fs, 0.5 * pb + 0.5 * pc

    def eval(self, ctx, si, wo, active=True):
        return self.eval_pdf(ctx, si, wo, active)[0]

    def pdf(self, ctx, si, wo, active=True):
        return self.eval_pdf(ctx, si, wo, active)[1]

    def sample(self, ctx, si, sample1, sample2, active=True):
        take_base = sample1 < 0.5
        bs, _ = self.base.sample(ctx, si, dr.minimum(2.0 * sample1, 0.99999994), sample2, active)
        cosine = mi.warp.square_to_cosine_hemisphere(sample2)
        bs.wo = dr.select(take_base, bs.wo, cosine)
        bs.eta = dr.select(take_base, bs.eta, 1.0)
        bs.sampled_type = dr.select(take_base, bs.sampled_type,
                                    mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
        f, bs.pdf = self.eval_pdf(ctx, si, bs.wo, active)
        ok = active & (bs.pdf > 0)
        return bs, dr.select(ok, f / dr.maximum(bs.pdf, 1e-20), 0.0)

    def eval_diffuse_reflectance(self, si, active=True):
        return self.base.eval_diffuse_reflectance(si, active)

    def traverse(self, callback):
        pass

    def to_string(self):
        return f"Sheen[weight={self.weight}, {self.base}]"


class ClearCoat(mi.BSDF):
    """vkrt's clear coat (docs/materials.md, "The clear coat"), one-sided over a nested Mitsuba
    BSDF, written from the documentation: the coat reflects weight x F(wo.h) D G / (4 cos_i)
    (GGX of index 1.5, Mitsuba's distribution and Fresnel); the base beneath is scaled by
    T(cos_i) T(cos_o) / (1 - w Fdr), T = 1 - w F (the smooth coat's Fresnel), or for a glass base
    (one that transmits) by T on each side where the light crosses the coat: both for its
    reflection on the front, one for its transmission, nothing for its reflection inside, and the
    coat reflects only on the front. (Mitsuba's wi is the viewer's direction, vkrt's o.) Sampled
    otherwise than vkrt: the coat with probability 1/2, the base's own sampling else, so that the
    two renders share the model but not the estimator."""

    ETA = 1.5

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.base = props["base"]
        self.weight = float(props["weight"])
        self.distr = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, float(props["alpha"]),
                                               True)
        # Fdr = 2 int_0^1 F(mu) mu dmu, by the midpoint rule (the unpolarised Fresnel of a
        # dielectric, written out: np arrays rather than Mitsuba's Float).
        mu = (np.arange(20000) + 0.5) / 20000
        ct = np.sqrt(1.0 - (1.0 - mu * mu) / self.ETA ** 2)
        rs = (mu - self.ETA * ct) / (mu + self.ETA * ct)
        rp = (self.ETA * mu - ct) / (self.ETA * mu + ct)
        self.fdr = float(2.0 * np.mean(0.5 * (rs * rs + rp * rp) * mu))
        self.glass = mi.has_flag(self.base.flags(), mi.BSDFFlags.Transmission)
        self.m_components = [self.base.flags(i) for i in range(self.base.component_count())] + [
            mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide]
        self.m_flags = self.base.flags() | mi.BSDFFlags.GlossyReflection

    def _t(self, cos):
        return 1.0 - self.weight * mi.fresnel(dr.abs(cos), mi.Float(self.ETA))[0]

    def _scale(self, si, wo):
        ci, co = mi.Frame3f.cos_theta(si.wi), mi.Frame3f.cos_theta(wo)
        if not self.glass:
            return self._t(ci) * self._t(co) / (1.0 - self.weight * self.fdr)
        front = ci > 0
        reflected = ci * co > 0
        return dr.select(front, dr.select(reflected, self._t(ci) * self._t(co), self._t(ci)),
                         dr.select(reflected, 1.0, self._t(co)))

    def _coat(self, si, wo, active):
        """f cos of the coat's reflection (front side only), and the density of drawing wo by
        reflecting wi about a visible normal, which counts directions below the surface too (a
        glass base lets light through there)."""
        ci, co = mi.Frame3f.cos_theta(si.wi), mi.Frame3f.cos_theta(wo)
        ok = active & (ci > 0)
        h = dr.normalize(si.wi + wo)
        f = (self.weight * mi.fresnel(dr.dot(wo, h), mi.Float(self.ETA))[0] *
             self.distr.eval(h) * self.distr.G(si.wi, wo, h) / (4.0 * dr.maximum(ci, 1e-8)))
        pdf = self.distr.pdf(si.wi, h) / (4.0 * dr.maximum(dr.dot(wo, h), 1e-8))
        return dr.select(ok & (co > 0), f, 0.0), dr.select(ok, pdf, 0.0)

    def _pc(self, si):
        return dr.select(mi.Frame3f.cos_theta(si.wi) > 0, 0.5, 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        fb, pb = self.base.eval_pdf(ctx, si, wo, active)
        fc, pcoat = self._coat(si, wo, active)
        pc = self._pc(si)
        return fb * self._scale(si, wo) + fc, (1.0 - pc) * pb + pc * pcoat

    def eval(self, ctx, si, wo, active=True):
        return self.eval_pdf(ctx, si, wo, active)[0]

    def pdf(self, ctx, si, wo, active=True):
        return self.eval_pdf(ctx, si, wo, active)[1]

    def sample(self, ctx, si, sample1, sample2, active=True):
        pc = self._pc(si)
        take_coat = sample1 < pc
        u1 = dr.select(take_coat, 0.0, (sample1 - pc) / dr.maximum(1.0 - pc, 1e-8))
        bs, _ = self.base.sample(ctx, si, u1, sample2, active)
        m, _ = self.distr.sample(si.wi, sample2)
        coat_wo = 2.0 * dr.dot(si.wi, m) * m - si.wi
        bs.wo = dr.select(take_coat, coat_wo, bs.wo)
        bs.eta = dr.select(take_coat, 1.0, bs.eta)
        bs.sampled_type = dr.select(take_coat, mi.UInt32(+mi.BSDFFlags.GlossyReflection),
                                    bs.sampled_type)
        f, bs.pdf = self.eval_pdf(ctx, si, bs.wo, active)
        ok = active & (bs.pdf > 0)
        return bs, dr.select(ok, f / dr.maximum(bs.pdf, 1e-20), 0.0)

    def eval_diffuse_reflectance(self, si, active=True):
        return self.base.eval_diffuse_reflectance(si, active) * self._t(
            mi.Frame3f.cos_theta(si.wi))

    def traverse(self, callback):
        pass

    def to_string(self):
        return f"ClearCoat[weight={self.weight}, {self.base}]"


class Whitted(mi.SamplingIntegrator):
    """vkrt's light transport with Mitsuba's parts. At every hit: the emission of the surface,
    the direct light of every delta light (point, spot, directional) and of every area emitter
    (one point on each, by area: vkrt draws one point over all its emissive triangles by power,
    another unbiased estimate of the same light), each one sampled, shadow-tested and weighted by
    the BSDF (Mitsuba's), plus ambient x albedo (Mitsuba's
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
        # Delta lights (a directional one is also Infinite, as the environment is) and area
        # emitters (Surface); not the environment, which only rays that leave the scene see.
        lights = [e for e in scene.emitters()
                  if mi.has_flag(e.flags(), mi.EmitterFlags.Delta)
                  or mi.has_flag(e.flags(), mi.EmitterFlags.Surface)]
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
mi.register_bsdf("vkrt_twosided", lambda props: VkrtTwoSided(props))
mi.register_bsdf("vkrt_coat", lambda props: ClearCoat(props))
mi.register_bsdf("vkrt_sheen", lambda props: Sheen(props))
mi.register_integrator("vkrt_whitted", lambda props: Whitted(props))

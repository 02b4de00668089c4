#!/usr/bin/env python3
"""Renders a Euclidean mirror room with Mitsuba 3 and with `orbifold render`, and compares them.

A peer-renderer check of the light transport: the room is exported with `orbifold room` (at
its true size: export coordinates are twice the model's, docs/room.md) and read as the renderer
reads it (`orbifold scene show --json`). Its walls, floor, ceiling and objects become Mitsuba
meshes with the exported normals: colours, checkerboards and image textures become `diffuse`
(over our texture coordinates, docs/scene-format.md; an object's solid checkerboard through a
small Python texture, `solid_checker`, and procedural marble through a port of ours,
`marble`), mirrors perfect conductors of the same reflectance, glass `dielectric`, metals
`roughconductor` (GGX, our complex indices) and plastic `roughplastic` (GGX over a diffuse base,
`nonlinear`; ours uses smooth-interface transmittances where Mitsuba tabulates rough ones). Sphere lights
become the same 352-triangle Lambertian polyhedron, rectangle lights rectangles facing the same
way, point and spot lights (in rooms without mirrors) Mitsuba's `point` and a hard-edged `spot`,
and the camera the same pinhole camera. Both images are linear EXR with a box pixel filter. Mitsuba's
path tracer finds the light through mirrors and glass only by hitting it; ours samples it
through its mirror images — the two must agree within their noise.

Each renderer renders SEEDS images with different seeds; the standard error of every 8×8 block
comes from their spread. The script prints the mean luminance ratio and the distribution of
the blocks' z-scores (difference over its standard error) and writes a picture: ours, Mitsuba's,
and the blocks' z-scores (white: agreement; red: ours brighter, blue: darker, full at 3 standard
errors).

Needs `pip install mitsuba numpy pillow` (3.x; `--variant llvm_ad_rgb` is faster where
Dr.Jit finds a recent libLLVM, such as Debian's libllvm19 (with the dev VM's 14 or 15 it failed
to compile its kernels: "Cannot select ... fminimum"; DRJIT_LIBLLVM_PATH chooses one); the
default is scalar_rgb, where a marble runs a Python function at every lookup: slow) and a
release build (`cargo build --release -p orbifold-cli`).

    python3 scripts/compare-mitsuba.py examples/peer/mirrors-2222.toml \
        [--size 160x120] [--spp 1024] [--orbifold-spp 256] [--seeds 4] [--out DIR] \
        [--orbifold-args "--no-radiance-cache --no-footprint"]
"""
import argparse
import json
import math
import os
import shlex
import subprocess
import sys
import tempfile
import time

import numpy as np

BINARY = os.environ.get("ORBIFOLD", "target/release/orbifold")
EXPORT_SCALE = 2.0  # orbifold_scene::geometry::EXPORT_SCALE
BLOCK = 8


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("scene")
    p.add_argument("--size", default="160x120")
    p.add_argument("--spp", type=int, default=1024, help="Mitsuba samples per pixel, per seed")
    p.add_argument("--orbifold-spp", type=int, default=256, help="ours, per seed")
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--out", default="peer-out")
    p.add_argument("--orbifold-args", default="--no-radiance-cache --no-footprint",
                   help="extra arguments for `orbifold render` (default: unbiased, no cache)")
    p.add_argument("--variant", default=None, help="Mitsuba variant (default scalar_rgb)")
    return p.parse_args()


def read_obj(path):
    """Groups of an OBJ written by `orbifold room`: name -> (material, positions, normals, faces,
    texture coordinates or None)."""
    v, vn, vt, groups, current = [], [], [], {}, None
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            v.append([float(x) for x in parts[1:4]])
        elif parts[0] == "vn":
            vn.append([float(x) for x in parts[1:4]])
        elif parts[0] == "vt":
            vt.append([float(x) for x in parts[1:3]])
        elif parts[0] == "o":
            current = groups.setdefault(parts[1], {"material": None, "faces": []})
        elif parts[0] == "usemtl":
            current["material"] = parts[1]
        elif parts[0] == "f":
            # v//vn, or v/vt/vn in a textured group: (v, vn, vt or -1) per corner.
            corners = []
            for c in parts[1:]:
                a, t, n = (c.split("/") + ["", ""])[:3]
                corners.append((int(a) - 1, int(n) - 1, int(t) - 1 if t else -1))
            current["faces"].append(corners)
    v, vn, vt = np.array(v), np.array(vn), np.array(vt)
    out = {}
    for name, g in groups.items():
        corners = [c for f in g["faces"] for c in f]
        keys = sorted(set(corners))
        index = {k: i for i, k in enumerate(keys)}
        positions = np.array([v[a] for a, _, _ in keys])
        normals = np.array([vn[b] for _, b, _ in keys])
        uv = np.array([vt[t] for _, _, t in keys]) if keys[0][2] >= 0 else None
        faces = np.array([[index[c] for c in f] for f in g["faces"]], dtype=np.uint32)
        out[name] = (g["material"], positions, normals, faces, uv)
    return out


def check_exported_uv(group, ours, exported):
    """The export's texture coordinates (OBJ: v upwards) must be the ones the script derives from
    the scene: a check of `orbifold room`'s textures, through the peer comparison."""
    if exported is None:
        sys.exit(f"error: the export has no texture coordinates for the textured group {group!r}")
    worst = float(np.abs(exported - ours).max())
    if worst > 1e-4 * max(1.0, float(np.abs(ours).max())):
        sys.exit(f"error: group {group!r}: the exported texture coordinates differ from the scene's "
                 f"by up to {worst:.3g}")


def read_mtl(path):
    materials, current = {}, None
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "newmtl":
            current = materials.setdefault(parts[1], {})
        elif parts[0] in ("Kd", "Ks"):
            current[parts[0]] = [float(x) for x in parts[1:4]]
        elif parts[0] == "illum":
            current["illum"] = int(parts[1])
    return materials


def write_ply(path, positions, normals, faces, uv=None):
    columns = [positions, normals] + ([uv] if uv is not None else [])
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(positions)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              "property float nx\nproperty float ny\nproperty float nz\n"
              + ("property float u\nproperty float v\n" if uv is not None else "")
              + f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    vertices = np.hstack(columns).astype("<f4")
    rows = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    rows["n"], rows["i"] = 3, faces
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(vertices.tobytes())
        f.write(rows.tobytes())


def write_sphere_light(path, centre, radius, segments=16, rings=12):
    """Our sphere light exactly: `uv_sphere(0.5, 16, 12)` (orbifold_scene::mesh::procedural)
    scaled to `radius`, as orbifold_render::light builds it — object (ρ cos φ, y, ρ sin φ) is
    (ρ cos φ, −ρ sin φ, y) in the room — a Lambertian polyhedron of the light's power (radiance
    P / (π × its area), not a sphere's). Writes it with a face normal per triangle, facing out;
    returns its area."""
    def point(k, j):
        theta, phi = math.pi * k / rings, 2 * math.pi * j / segments
        rho, y = radius * math.sin(theta), radius * math.cos(theta)
        return centre + np.array([rho * math.cos(phi), -rho * math.sin(phi), y])
    triangles = []
    for j in range(segments):
        triangles.append([point(0, 0), point(1, j), point(1, j + 1)])
        triangles.append([point(rings, 0), point(rings - 1, j), point(rings - 1, j + 1)])
        for k in range(1, rings - 1):
            a, b, c, e = point(k, j), point(k, j + 1), point(k + 1, j), point(k + 1, j + 1)
            triangles += [[a, b, e], [a, e, c]]
    positions, normals, area = [], [], 0.0
    for t in triangles:
        n = np.cross(t[1] - t[0], t[2] - t[0])
        if np.dot(n, sum(t) / 3 - centre) < 0:
            t, n = [t[0], t[2], t[1]], -n
        area += 0.5 * np.linalg.norm(n)
        positions += t
        normals += [n / np.linalg.norm(n)] * 3
    faces = np.arange(len(positions), dtype=np.uint32).reshape(-1, 3)
    write_ply(path, np.array(positions), np.array(normals), faces)
    return area


def identifier(name):
    return "".join("_" if c.isspace() else c for c in name)


def scene_material(scene, group):
    """The scene's material of an exported group (None for a mirror)."""
    room = scene["room"]
    if group == "floor":
        return "room.floor", room["floor"]
    if group == "ceiling":
        return "room.ceiling", room["ceiling"]
    if group.startswith("mirror_"):
        return group, None
    if group.startswith("wall_"):
        index = int(group[5:])
        for i, wall in enumerate(scene.get("walls", [])):
            if wall["index"] == index and wall.get("material") is not None:
                return f"walls[{i}].material", wall["material"]
        return "room.wall_material", room["wall_material"]
    for i, obj in enumerate(scene.get("objects", [])):
        if identifier(obj.get("name", f"object {i}")) == group:
            return f"objects[{i}].material", obj["material"]
    sys.exit(f"error: the export has a group {group!r} that the scene does not name")


def wall_frames(scene):
    """Each wall's start corner and unit direction in export coordinates (from `orbifold layout`
    of the scene's polygon): textures on walls are laid out by (length along the wall from its
    corner i, height)."""
    o = scene["orbifold"]
    cmd = [BINARY, "layout", o["signature"], "--shape", o.get("shape", "default"),
           "--at", ",".join(str(v) for v in o.get("at", [0.0, 0.0])),
           "--angle", str(o.get("angle", 0.0)), "--json"]
    if o.get("parameters"):
        cmd[3:3] = ["--params", ",".join(str(v) for v in o["parameters"])]
    layout = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
    corner = [np.array([v["x"], v["y"]]) * EXPORT_SCALE for v in layout["vertices"]]
    frames = []
    for e in layout["edges"]:
        a, b = corner[e["from"]], corner[e["to"]]
        frames.append((a, (b - a) / np.linalg.norm(b - a)))
    return frames


def texture_coordinates(scene, where, group, material, positions):
    """Our texture coordinates (orbifold_render::integrator, `Integrator::surface`) at the exported
    vertices, in intrinsic units: on a wall (length along it, height, 0); elsewhere (x, y, height)
    in the model, or in the logarithm map at the room's centre (in the Euclidean plane: the offset
    from it, at true size). Both are affine in the exported position, so Mitsuba's interpolation
    across a triangle is exact."""
    if group.startswith("wall_"):
        start, direction = wall_frames(scene)[int(group[5:])]
        along = (positions[:, :2] - start) @ direction
        return np.stack([along, positions[:, 2], np.zeros(len(positions))], axis=1)
    if material.get("coordinates", "model") == "intrinsic":
        if scene["orbifold"].get("angle", 0.0) != 0.0:
            sys.exit(f"error: {where}: intrinsic coordinates in a turned room (orbifold.angle)")
        centre = np.array(scene["orbifold"].get("at", [0.0, 0.0])) * EXPORT_SCALE
        xy = positions[:, :2] - centre
    else:
        xy = positions[:, :2] / EXPORT_SCALE
    return np.concatenate([xy, positions[:, 2:3]], axis=1)


def on_a_surface_of_the_room(where, group):
    return where in ("room.floor", "room.ceiling") or group.startswith("wall_")


def solid_checker(scene, where, group, material):
    """On an object ours is a solid checker: colour ⌊p₀/size⌋ + ⌊p₁/size⌋ + ⌊p₂/size⌋ mod 2 of
    the texture coordinates p, affine in the position (`texture_coordinates`). Mitsuba has no
    solid texture: `solid_checker` (registered by `register_solid_checker`) evaluates ours at
    the hit's position, with the affine map read off three points."""
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    t = texture_coordinates(scene, where, group, material, points)
    linear = (t[1:] - t[0]).T
    if not np.allclose(linear, np.diag(np.diag(linear)), atol=1e-12):
        sys.exit(f"error: {where}: texture coordinates that mix the axes")
    (a, b), colours = material["colors"], {}
    for name, colour in (("color0", a), ("color1", b)):
        for channel, value in zip("rgb", colour):
            colours[f"{name}_{channel}"] = float(value)
    return {"type": "solid_checker", "size": float(material["size"]),
            **{f"scale_{axis}": float(linear[i, i]) for i, axis in enumerate("xyz")},
            **{f"offset_{axis}": float(t[0, i]) for i, axis in enumerate("xyz")}, **colours}


def register_solid_checker(mi):
    """Registers `solid_checker`: a Mitsuba texture that is our solid checkerboard of objects
    (`solid_checker`), evaluated at the hit's world position (Dr.Jit arithmetic, so that it
    runs in the scalar and the vectorised variants alike)."""
    import drjit as dr

    class SolidChecker(mi.Texture):
        def __init__(self, props):
            mi.Texture.__init__(self, props)
            self.size = props["size"]
            self.scale = [props[f"scale_{a}"] for a in "xyz"]
            self.offset = [props[f"offset_{a}"] for a in "xyz"]
            self.colours = [mi.Color3f(*(props[f"color{k}_{c}"] for c in "rgb")) for k in (0, 1)]

        def eval(self, si, active=True):
            parity = 0
            for i, x in enumerate((si.p.x, si.p.y, si.p.z)):
                parity = parity + dr.floor((x * self.scale[i] + self.offset[i]) / self.size)
            odd = parity - 2.0 * dr.floor(0.5 * parity) > 0.5
            return dr.select(odd, self.colours[1], self.colours[0])

        def eval_1(self, si, active=True):
            return mi.luminance(self.eval(si, active))

        def mean(self):
            return 0.5 * (mi.luminance(self.colours[0]) + mi.luminance(self.colours[1]))

        def traverse(self, callback):
            pass

        def to_string(self):
            return "SolidChecker[our solid checkerboard of objects]"

    mi.register_texture("solid_checker", lambda props: SolidChecker(props))


def affine_texture_map(scene, where, group, material, positions):
    """Our texture coordinates p = A x + b of an exported position x (`texture_coordinates`, affine
    in x on each part: on a wall too), read off four points and checked at the part's vertices."""
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    t = texture_coordinates(scene, where, group, material, points)
    linear, offset = (t[1:] - t[0]).T, t[0]
    expected = texture_coordinates(scene, where, group, material, positions)
    worst = float(np.abs(positions @ linear.T + offset - expected).max())
    if worst > 1e-9 * max(1.0, float(np.abs(expected).max())):
        sys.exit(f"error: {where}: texture coordinates that are not affine in the position")
    return linear, offset


def marble(scene, where, group, material, positions):
    """Our procedural marble (orbifold_render::bsdf::marble) at the texture coordinates p, at the
    frequency 1/scale (orbifold_render::integrator, `Look::Marble`): `marble`, registered by
    `register_marble`, evaluates it at the hit's position through the affine map to p."""
    linear, offset = affine_texture_map(scene, where, group, material, positions)
    props = {"type": "marble", "frequency": 1.0 / float(material["scale"])}
    for r in range(3):
        props[f"offset_{r}"] = float(offset[r])
        for c in range(3):
            props[f"linear_{r}{c}"] = float(linear[r, c])
    for name in ("base", "vein"):
        for channel, value in zip("rgb", material[name]):
            props[f"{name}_{channel}"] = float(value)
    return props


# Perlin's 12 cube-edge gradients, in the order of orbifold_render::bsdf::lattice_gradient.
GRADIENTS = [(1, 1, 0), (-1, 1, 0), (1, -1, 0), (-1, -1, 0), (1, 0, 1), (-1, 0, 1), (1, 0, -1),
             (-1, 0, -1), (0, 1, 1), (0, -1, 1), (0, 1, -1), (0, -1, -1)]
MASK64 = (1 << 64) - 1


def marble_vein_weight(mi, q):
    """The veins' weight t in [0, 1] of orbifold_render::bsdf::marble at the point q (already
    times the frequency), a port of its Rust line by line, in double precision: a sine of
    q₀ + q₁/2 + 3 turbulence (6 octaves of |gradient noise|: Perlin's improved noise, quintic
    fade, each lattice point's gradient chosen by SplitMix64 hashes of its integer coordinates).
    `q` holds Python floats in the scalar variants, Dr.Jit Float64 arrays in the others (64-bit
    integer arithmetic wraps there as in Rust; Python's integers are masked to 64 bits)."""
    import drjit as dr
    if mi.variant().startswith("scalar"):
        floor, absolute, sin, wrap = math.floor, abs, math.sin, lambda x: x & MASK64
        lattice = lambda c: int(c)
        as_u64 = lambda i: i & MASK64
        gradient = lambda h, axis: float(GRADIENTS[h % 12][axis])
        clamp01 = lambda x: min(max(x, 0.0), 1.0)
    else:
        floor, absolute, sin, wrap = dr.floor, dr.abs, dr.sin, lambda x: x
        lattice = lambda c: mi.Int64(c)
        as_u64 = lambda i: dr.reinterpret_array(mi.UInt64, i)
        tables = [mi.Float64([float(g[axis]) for g in GRADIENTS]) for axis in range(3)]
        gradient = lambda h, axis: dr.gather(mi.Float64, tables[axis], mi.UInt32(h % 12))
        # dr.clip on Float64 becomes LLVM's fminimum, which LLVM 14-15 cannot compile on x86.
        clamp01 = lambda x: dr.select(x < 0.0, 0.0, dr.select(x > 1.0, 1.0, x))

    def splitmix64(x):
        z = wrap(x + 0x9E3779B97F4A7C15)
        z = wrap((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9)
        z = wrap((z ^ (z >> 27)) * 0x94D049BB133111EB)
        return z ^ (z >> 31)

    def fade(t):
        return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)

    def lerp(t, a, b):
        return a + t * (b - a)

    def gradient_noise(p):
        cell = [floor(x) for x in p]
        f = [x - c for x, c in zip(p, cell)]
        i = [lattice(c) for c in cell]
        u, v, w = (fade(t) for t in f)

        def corner(dx, dy, dz):
            h = splitmix64(splitmix64(splitmix64(as_u64(i[0] + dx)) ^ as_u64(i[1] + dy))
                           ^ as_u64(i[2] + dz))
            return (gradient(h, 0) * (f[0] - dx) + gradient(h, 1) * (f[1] - dy)
                    + gradient(h, 2) * (f[2] - dz))
        x00 = lerp(u, corner(0, 0, 0), corner(1, 0, 0))
        x10 = lerp(u, corner(0, 1, 0), corner(1, 1, 0))
        x01 = lerp(u, corner(0, 0, 1), corner(1, 0, 1))
        x11 = lerp(u, corner(0, 1, 1), corner(1, 1, 1))
        return lerp(w, lerp(v, x00, x10), lerp(v, x01, x11))

    turbulence, frequency = 0.0, 1.0
    for _ in range(6):
        turbulence = turbulence + absolute(gradient_noise([x * frequency for x in q])) / frequency
        frequency *= 2.0
    s = sin(math.pi * (q[0] + 0.5 * q[1] + 3.0 * turbulence))
    t = clamp01(1.0 - absolute(s))
    return (t * t) * (t * t)


def register_marble(mi):
    """Registers `marble`: a Mitsuba texture that is our procedural marble (`marble`), evaluated
    at the hit's world position in double precision (Dr.Jit arithmetic in the vectorised
    variants; in the scalar ones a Python function per lookup: slow)."""
    import drjit as dr

    class Marble(mi.Texture):
        def __init__(self, props):
            mi.Texture.__init__(self, props)
            self.frequency = props["frequency"]
            self.linear = [[props[f"linear_{r}{c}"] for c in range(3)] for r in range(3)]
            self.offset = [props[f"offset_{r}"] for r in range(3)]
            self.base = [props[f"base_{c}"] for c in "rgb"]
            self.vein = [props[f"vein_{c}"] for c in "rgb"]

        def eval(self, si, active=True):
            x = [mi.Float64(si.p.x), mi.Float64(si.p.y), mi.Float64(si.p.z)]
            p = [self.linear[r][0] * x[0] + self.linear[r][1] * x[1] + self.linear[r][2] * x[2]
                 + self.offset[r] for r in range(3)]
            t = marble_vein_weight(mi, [c * self.frequency for c in p])
            channels = []
            for base, vein in zip(self.base, self.vein):
                c, lo, hi = base + (vein - base) * t, min(base, vein), max(base, vein)
                channels.append(mi.Float(dr.select(c < lo, lo, dr.select(c > hi, hi, c))))
            return mi.Color3f(*channels)

        def eval_1(self, si, active=True):
            return mi.luminance(self.eval(si, active))

        def mean(self):
            return mi.luminance(mi.Color3f(*self.base))

        def traverse(self, callback):
            pass

        def to_string(self):
            return "Marble[our procedural marble]"

    mi.register_texture("marble", lambda props: Marble(props))


def checker_uv(scene, where, group, material, positions):
    """Mitsuba's checkerboard is color0 where ⌊2u⌋ + ⌊2v⌋ is even; ours takes colour
    ⌊p₀/size⌋ + ⌊p₁/size⌋ + ⌊p₂/size⌋ mod 2 of the texture coordinates p. On the floor, the
    ceiling and the walls the coordinate that Mitsuba's two lack is constant (the height; 0 on a
    wall), so u, v = p / (2 size) with the colours swapped when that constant's square is odd."""
    size = material["size"]
    p = texture_coordinates(scene, where, group, material, positions)
    if group.startswith("wall_"):
        return p[:, :2] / (2 * size), False
    flipped = math.floor(positions[0, 2] / size) % 2 == 1
    return p[:, :2] / (2 * size), flipped


def image_uv(scene, where, group, material, positions):
    """Ours looks up texel (p₀/scale, p₁/scale) of the texture coordinates p with v upwards (the
    image's bottom row at v = 0), repeated, nearest texel; Mitsuba's bitmap has v downwards."""
    p = texture_coordinates(scene, where, group, material, positions) / material["scale"]
    return np.stack([p[:, 0], -p[:, 1]], axis=1)


def check_materials(scene):
    """The comparison needs materials that Mitsuba has exactly."""
    room = scene["room"]
    found = [("room.floor", room["floor"]), ("room.ceiling", room["ceiling"]),
             ("room.wall_material", room["wall_material"])]
    found += [(f"walls[{i}].material", w.get("material")) for i, w in enumerate(scene.get("walls", []))]
    found += [(f"objects[{i}].material", o["material"]) for i, o in enumerate(scene.get("objects", []))]
    for where, material in found:
        if material is not None and material["kind"] not in ("color", "checker", "texture", "glass",
                                                             "metal", "plastic", "marble"):
            sys.exit(f"error: {where}: a {material['kind']!r} material cannot be compared")


# Complex indices of refraction (η, k per RGB channel) of the named metals: the values of
# `orbifold_render::bsdf::Bsdf::{silver, gold, copper, aluminium}` (keep them in step), so that
# Mitsuba's rough conductor gets the same Fresnel term as ours.
METALS = {
    "silver": ([0.1552646489, 0.1167232965, 0.1383806959], [4.8283433224, 3.1222459278, 2.1469504455]),
    "gold": ([0.1431189557, 0.3749570432, 1.4424785571], [3.9831604247, 2.3857207478, 1.6032152899]),
    "copper": ([0.2004376970, 0.9240334304, 1.1022119527], [3.9129485033, 2.4528477015, 2.1421879552]),
    "aluminium": ([1.6574599595, 0.8803689579, 0.5212287346], [9.2238691996, 6.2695232477, 4.8370012281]),
}
PLASTIC_ETA = 1.5  # orbifold_render::bsdf::PLASTIC_ETA


def rgb(value):
    return {"type": "rgb", "value": list(value)}


def mitsuba_bsdf(scene, scene_dir, group, mtl, positions):
    """The Mitsuba BSDF of an exported group, and its texture coordinates if it needs them
    (`scene_dir`: where the scene's relative texture paths start)."""
    where, material = scene_material(scene, group)
    if material is None:
        return {"type": "twosided", "bsdf": {"type": "conductor", "material": "none",
                                             "specular_reflectance": rgb(mtl["Ks"])}}, None
    kind = material["kind"]
    if kind == "metal":
        eta, k = METALS[material["metal"]]
        if material["roughness"] < 1e-3:  # orbifold_render::bsdf::DELTA_ROUGHNESS
            bsdf = {"type": "conductor", "eta": rgb(eta), "k": rgb(k)}
        else:
            bsdf = {"type": "roughconductor", "distribution": "ggx", "alpha": material["roughness"],
                    "eta": rgb(eta), "k": rgb(k)}
        return {"type": "twosided", "bsdf": bsdf}, None
    if kind == "plastic":
        # Ours sums the light's bounces between the base and the coat, ρ/(1 − ρ F̄ᵢₙₜ): Mitsuba's
        # `nonlinear` mode (its default divides by 1 − F̄ᵢₙₜ alone, brighter for dark bases).
        bsdf = {"type": "plastic", "int_ior": PLASTIC_ETA, "ext_ior": 1.0, "nonlinear": True,
                "diffuse_reflectance": rgb(material["color"])}
        if material["roughness"] >= 1e-3:
            bsdf.update(type="roughplastic", distribution="ggx", alpha=material["roughness"])
        return {"type": "twosided", "bsdf": bsdf}, None
    if kind == "glass":
        return {"type": "dielectric", "int_ior": material["ior"], "ext_ior": 1.0,
                "specular_transmittance": rgb(material["tint"])}, None
    if kind == "checker" and not on_a_surface_of_the_room(where, group):
        texture = solid_checker(scene, where, group, material)
        return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": texture}}, None
    if kind == "marble":
        texture = marble(scene, where, group, material, positions)
        return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": texture}}, None
    if kind == "checker":
        uv, flipped = checker_uv(scene, where, group, material, positions)
        a, b = material["colors"][::-1] if flipped else material["colors"]
        texture = {"type": "checkerboard", "color0": rgb(a), "color1": rgb(b)}
        return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": texture}}, uv
    if kind == "texture":
        # sRGB 8-bit texels decoded to linear, as ours does (orbifold_render::texture).
        path = os.path.join(scene_dir, material["path"])
        texture = {"type": "bitmap", "filename": path, "filter_type": "nearest",
                   "wrap_mode": "repeat", "raw": False}
        uv = image_uv(scene, where, group, material, positions)
        return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": texture}}, uv
    return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": rgb(material["color"])}}, None


def mitsuba_scene(mi, scene, scene_dir, groups, materials, width, height, tmp):
    camera = scene["camera"]
    at = np.array(camera["at"]) * EXPORT_SCALE
    yaw, pitch = math.radians(camera["yaw"]), math.radians(camera["pitch"])
    eye = [at[0], at[1], camera["height"]]
    forward = [math.cos(pitch) * math.cos(yaw), math.cos(pitch) * math.sin(yaw), math.sin(pitch)]
    if camera["kind"] != "pinhole":
        sys.exit("error: camera.kind: only the pinhole camera can be compared")
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": -1},
        "sensor": {
            "type": "perspective",
            "fov_axis": "y",
            "fov": camera["fov"],
            "near_clip": 1e-3,
            "to_world": mi.ScalarTransform4f().look_at(
                origin=eye, target=[e + f for e, f in zip(eye, forward)], up=[0, 0, 1]),
            "film": {"type": "hdrfilm", "width": width, "height": height,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
            "sampler": {"type": "independent"},
        },
    }
    for name, (material, positions, normals, faces, exported_uv) in groups.items():
        path = os.path.join(tmp, f"{name}.ply")
        bsdf, uv = mitsuba_bsdf(scene, scene_dir, name, materials[material], positions)
        if uv is not None:
            # Mitsuba's bitmaps have v downwards; its checkerboard is symmetric in v.
            image = bsdf["bsdf"]["reflectance"]["type"] == "bitmap"
            check_exported_uv(name, uv * [1.0, -1.0] if image else uv, exported_uv)
        write_ply(path, positions, normals, faces, uv)
        d[name.replace(".", "_")] = {"type": "ply", "filename": path, "bsdf": bsdf}
    for i, light in enumerate(scene.get("lights", [])):
        kind = light["kind"]
        colour = np.array(light["color"]) * light["power"]
        at = np.array(light["at"]) * EXPORT_SCALE
        h = light["height"]
        if kind == "sphere":
            path = os.path.join(tmp, f"light-{i}.ply")
            area = write_sphere_light(path, np.array([at[0], at[1], h]), light["radius"])
            d[f"light {i}"] = {"type": "ply", "filename": path, "face_normals": True,
                               "bsdf": {"type": "diffuse", "reflectance": rgb([0.0, 0.0, 0.0])},
                               "emitter": {"type": "area", "radiance": rgb(colour / (math.pi * area))}}
        elif kind == "rectangle":
            # Ours: a rectangle facing `axis`, its width along axis × up (or +x when the axis is
            # vertical), its height along axis × that (orbifold_render::light::rectangle).
            w, l = light["size"]
            axis = light_axis(light)
            right = np.cross(axis, [0.0, 0.0, 1.0])
            right = right / np.linalg.norm(right) if np.linalg.norm(right) > 1e-9 else np.array([1.0, 0, 0])
            up = np.cross(axis, right)
            radiance = colour / (math.pi * w * l)
            # Mitsuba's rectangle is [−1, 1]² in its xy-plane, emitting along +z.
            matrix = np.identity(4)
            matrix[:3, 0], matrix[:3, 1], matrix[:3, 2] = 0.5 * w * right, 0.5 * l * up, axis
            matrix[:3, 3] = [at[0], at[1], h]
            d[f"light {i}"] = {"type": "rectangle", "to_world": mi.ScalarTransform4f(matrix.tolist()),
                               "emitter": {"type": "area", "radiance": rgb(radiance)}}
        elif kind in ("point", "spot"):
            if any(name.startswith("mirror_") for name in groups):
                sys.exit(f"error: lights[{i}]: a {kind} light in a room with mirrors (Mitsuba's "
                         "point and spot lights never light a surface through a mirror)")
            if kind == "point":
                d[f"light {i}"] = {"type": "point", "position": [at[0], at[1], h],
                                   "intensity": rgb(colour / (4 * math.pi))}
            else:
                # Ours is a hard cone of intensity P / (2π(1 − cos θ)); Mitsuba's spot fades
                # linearly from `beam_width` to `cutoff_angle`: no fade.
                cone = light["cone"]
                axis = light_axis(light)
                eye = [at[0], at[1], h]
                d[f"light {i}"] = {
                    "type": "spot", "cutoff_angle": cone, "beam_width": cone * (1 - 1e-9),
                    "intensity": rgb(colour / (2 * math.pi * (1 - math.cos(math.radians(cone))))),
                    "to_world": mi.ScalarTransform4f().look_at(
                        origin=eye, target=[e + a for e, a in zip(eye, axis)],
                        up=[0, 0, 1] if abs(axis[2]) < 0.999 else [1, 0, 0]),
                }
        else:
            sys.exit(f"error: lights[{i}]: a {kind!r} light cannot be compared")
    return d


def light_axis(light):
    """Where a spot or rectangle light points: yaw from the model's +x axis, pitch up."""
    yaw, pitch = math.radians(light["yaw"]), math.radians(light["pitch"])
    return np.array([math.cos(pitch) * math.cos(yaw), math.cos(pitch) * math.sin(yaw), math.sin(pitch)])


def luminance(img):
    return img[..., :3] @ np.array([0.2126, 0.7152, 0.0722])


def blocks(img):
    h, w = img.shape[:2]
    h, w = h - h % BLOCK, w - w % BLOCK
    lum = luminance(img[:h, :w])
    return lum.reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK).mean(axis=(1, 3))


def tone(img, exposure):
    x = np.clip(img[..., :3] * exposure, 0, None)
    x = x / (1 + x)  # Reinhard: the same curve for both images
    return (255 * np.clip(x, 0, 1) ** (1 / 2.2)).astype(np.uint8)


def main():
    args = parse_args()
    width, height = (int(x) for x in args.size.split("x"))
    os.makedirs(args.out, exist_ok=True)
    # The scene as the renderer sees it, every default filled in.
    scene = json.loads(subprocess.run([BINARY, "scene", "show", args.scene, "--json"], check=True,
                                      capture_output=True, text=True).stdout)
    check_materials(scene)
    import mitsuba as mi
    variant = args.variant or "scalar_rgb"
    mi.set_variant(variant)
    register_solid_checker(mi)
    register_marble(mi)

    with tempfile.TemporaryDirectory() as tmp:
        report = json.loads(subprocess.run(
            [BINARY, "room", args.scene, "-o", f"{tmp}/room.obj", "--json"],
            check=True, capture_output=True, text=True).stdout)
        if report["geometry"] != "euclidean":
            sys.exit(f"error: {args.scene}: a {report['geometry']} room; only Euclidean rooms have a "
                     "peer renderer")
        groups = read_obj(f"{tmp}/room.obj")
        materials = read_mtl(f"{tmp}/room.mtl")
        ours, theirs, timing = [], [], {"orbifold": 0.0, "mitsuba": 0.0}
        for seed in range(args.seeds):
            out = f"{tmp}/ours-{seed}.exr"
            start = time.perf_counter()
            # The box filter, as Mitsuba's: ours defaults to a Gaussian (since 2026-11-25), which
            # blurs edges across the blocks' borders.
            subprocess.run([BINARY, "render", args.scene, "-o", out, "--size", args.size,
                            "--spp", str(args.orbifold_spp), "--no-adaptive", "--seed", str(seed),
                            "--filter", "box", *shlex.split(args.orbifold_args)],
                           check=True, capture_output=True)
            timing["orbifold"] += time.perf_counter() - start
            ours.append(np.array(mi.Bitmap(out), dtype=np.float64)[..., :3])
        d = mitsuba_scene(mi, scene, os.path.dirname(os.path.abspath(args.scene)), groups,
                         materials, width, height, tmp)
        mscene = mi.load_dict(d)
        for seed in range(args.seeds):
            start = time.perf_counter()
            img = mi.render(mscene, spp=args.spp, seed=seed)
            theirs.append(np.array(img, dtype=np.float64)[..., :3])
            timing["mitsuba"] += time.perf_counter() - start

    ours, theirs = np.array(ours), np.array(theirs)
    o_mean, t_mean = ours.mean(axis=0), theirs.mean(axis=0)
    ob = np.array([blocks(x) for x in ours])
    tb = np.array([blocks(x) for x in theirs])
    se2 = ob.var(axis=0, ddof=1) / args.seeds + tb.var(axis=0, ddof=1) / args.seeds
    diff = ob.mean(axis=0) - tb.mean(axis=0)
    z = diff / np.sqrt(np.maximum(se2, 1e-30))
    lit = tb.mean(axis=0) > 0.01 * tb.mean()
    rel = np.abs(diff[lit]) / tb.mean(axis=0)[lit]
    summary = {
        "scene": args.scene, "size": args.size, "mitsuba": f"{mi.__version__} {variant}",
        "seeds": args.seeds, "mitsuba_spp": args.spp, "orbifold_spp": args.orbifold_spp,
        "orbifold_args": args.orbifold_args,
        "mean_luminance": {"orbifold": float(luminance(o_mean).mean()),
                           "mitsuba": float(luminance(t_mean).mean())},
        "ratio": float(luminance(o_mean).mean() / luminance(t_mean).mean()),
        "ratio_standard_error": float(math.sqrt(
            luminance(ours).mean(axis=(1, 2)).var(ddof=1) / args.seeds
            + luminance(theirs).mean(axis=(1, 2)).var(ddof=1) / args.seeds) / luminance(t_mean).mean()),
        "blocks": int(z.size),
        "block_z": {"rms": float(np.sqrt((z ** 2).mean())), "over_3": float((np.abs(z) > 3).mean()),
                    "largest": float(np.abs(z).max())},
        "block_relative_difference": {"median": float(np.median(rel)), "p90": float(np.percentile(rel, 90)),
                                      "largest": float(rel.max())},
        "seconds": timing,
    }
    # Work-normalised noise: the mean relative pixel variance of one image times the seconds it
    # took. Their ratio is how many times longer Mitsuba takes to reach our noise (both on the
    # same cores), counting its fireflies.
    def variance_time(images, seconds):
        lum = luminance(images)
        relative = lum.var(axis=0, ddof=1) / (lum.mean(axis=0) + 0.01) ** 2
        return float(relative.mean()) * seconds / args.seeds
    summary["variance_times_seconds"] = {"orbifold": variance_time(ours, timing["orbifold"]),
                                         "mitsuba": variance_time(theirs, timing["mitsuba"])}
    summary["mitsuba_time_to_our_noise"] = (summary["variance_times_seconds"]["mitsuba"]
                                            / summary["variance_times_seconds"]["orbifold"])
    print(json.dumps(summary, indent=2))
    exposure = 0.18 / max(math.exp(np.log(luminance(t_mean) + 1e-4).mean()), 1e-6)
    from PIL import Image
    a, b = tone(o_mean, exposure), tone(t_mean, exposure)
    # The blocks' z-scores: red where ours is brighter, blue where darker, full at 3 standard errors.
    zmap = np.clip(np.kron(z, np.ones((BLOCK, BLOCK))) / 3, -1, 1)
    heat = np.full((height, width, 3), 255, dtype=np.uint8)
    zh, zw = zmap.shape
    heat[:zh, :zw, 1] = (255 * (1 - np.abs(zmap))).astype(np.uint8)
    heat[:zh, :zw, 0] = (255 * (1 - np.clip(-zmap, 0, 1))).astype(np.uint8)
    heat[:zh, :zw, 2] = (255 * (1 - np.clip(zmap, 0, 1))).astype(np.uint8)
    gap = np.full((height, 4, 3), 255, dtype=np.uint8)
    side = np.concatenate([a, gap, b, gap, heat], axis=1)
    name = os.path.splitext(os.path.basename(args.scene))[0]
    Image.fromarray(side).save(f"{args.out}/{name}.png")
    json.dump(summary, open(f"{args.out}/{name}.json", "w"), indent=2)
    np.savez_compressed(f"{args.out}/{name}.npz", orbifold=ours, mitsuba=theirs)


if __name__ == "__main__":
    main()

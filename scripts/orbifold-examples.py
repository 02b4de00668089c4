#!/usr/bin/env python3
"""Writes the example rooms of every kind of orbifold into examples/scenes/ (issue 58): the 17
wallpaper groups, spherical families and hyperbolic orbifolds with cone points, glides, handles
and cross-caps, each with the chiral letter p of the seed's Fig. 3.4 so that rotations,
reflections and glides show apart. The camera and the letter are placed from `orbifold layout
SYMBOL --json` (the polygon's centre and corners), so the files stay valid for the polygons the
tool builds. Usage: python3 scripts/orbifold-examples.py [--bin target/release/orbifold]"""
import argparse
import json
import math
import subprocess
from pathlib import Path

WALLPAPER = [
    ("p6m", "*632"), ("p6", "632"), ("p4m", "*442"), ("p4", "442"), ("p4g", "4*2"),
    ("p3m1", "*333"), ("p3", "333"), ("p31m", "3*3"), ("pmm", "*2222"), ("p2", "2222"),
    ("cmm", "2*22"), ("pmg", "22*"), ("cm", "*×"), ("pm", "**"), ("pgg", "22×"),
    ("pg", "××"), ("p1", "o"),
]
SPHERICAL = [
    ("icosahedral-rotations", "532"), ("octahedral-rotations", "432"),
    ("tetrahedral-rotations", "332"), ("pyritohedral", "3*2"), ("antiprismatic", "2*4"),
    ("dihedral-rotations", "225"), ("prism-rotations-with-mirror", "5*"),
    ("rotatory-reflection", "4×"), ("cyclic", "55"),
]
HYPERBOLIC = [
    ("four-cones", "2223"), ("cone-and-mirror", "4*3"), ("mirror-and-cross-cap", "*2×"),
    ("cone-and-two-cross-caps", "2××"), ("genus-two", "oo"),
    ("cone-of-order-two-and-a-mirror", "2*2222"),
]
ASCII = {"*": "s", "×": "x", "∞": "inf"}


def ascii_name(symbol):
    return "".join(ASCII.get(c, c) for c in symbol)


def layout(binary, symbol):
    out = subprocess.run([binary, "layout", symbol, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def scene(binary, symbol, title, comment):
    data = layout(binary, symbol)
    c = complex(data["centre"]["x"], data["centre"]["y"])
    corners = [complex(v["x"], v["y"]) for v in data["vertices"] if not v["ideal"]]
    if not corners:
        corners = [complex(v["x"], v["y"]) * 0.8 for v in data["vertices"]]
    far = max(corners, key=lambda z: abs(z - c))
    near = min(corners, key=lambda z: abs(z - c))
    # The camera a third of the way to the farthest corner, looking back past the centre at the
    # letter, which stands on the other side of the centre, a quarter of the nearest corner's
    # distance away.
    eye = c + (far - c) * 0.3
    away = (c - far) / abs(c - far)
    letter = c + away * abs(near - c) * 0.25
    yaw = math.degrees(math.atan2((letter - eye).imag, (letter - eye).real))
    size = min(0.35, 0.5 * abs(near - c)) if data["geometry"] != "euclidean" else 0.3
    construction = data.get("construction", "kaleidoscopic")
    if not construction.endswith("polygon"):
        construction += " polygon"
    return f"""# {title}: the orbifold {symbol} ({construction}). {comment}
# Written by scripts/orbifold-examples.py.

[orbifold]
signature = "{symbol}"

[room]
height = 1.0
mirrors = "all"
reflectance = [0.85, 0.85, 0.85]

[[objects]]
shape = "letter-p"
at = [{letter.real:.4f}, {letter.imag:.4f}]
size = {size:.3f}
yaw = 0.0
material = {{ kind = "color", color = [0.85, 0.3, 0.2] }}

[[lights]]
kind = "point"
at = [{c.real:.4f}, {c.imag:.4f}]
height = 0.9
power = 25.0

[camera]
at = [{eye.real:.4f}, {eye.imag:.4f}]
height = 0.6
yaw = {yaw:.1f}
pitch = -12.0
fov = 80.0
"""


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--bin", default="target/release/orbifold")
    args = parser.parse_args()
    out = Path(__file__).resolve().parent.parent / "examples" / "scenes"
    groups = (
        [(f"wallpaper-{name}-{ascii_name(s)}", s, f"Wallpaper group {name}",
          "Mirror walls reflect; paired walls are portals that carry you on from their partner.")
         for name, s in WALLPAPER]
        + [(f"spherical-{name}-{ascii_name(s)}", s, f"Spherical group {s} ({name.replace('-', ' ')})",
            "Its copies close up round the sphere.") for name, s in SPHERICAL]
        + [(f"hyperbolic-{name}-{ascii_name(s)}", s, f"Hyperbolic orbifold {s} ({name.replace('-', ' ')})",
            "Its copies spread out without end in H²×R.") for name, s in HYPERBOLIC]
        + [("fig-3.4-glide-next-to-a-mirror-sx", "*×", "Seed Fig. 3.4's letters in a room",
            "The letter p shows as q in the mirror wall and as b or d through the glide: a mirror "
            "next to a glide reflection (cm).")]
    )
    for name, symbol, title, comment in groups:
        path = out / f"{name}.toml"
        path.write_text(scene(args.bin, symbol, title, comment))
        print("wrote", path)


if __name__ == "__main__":
    main()

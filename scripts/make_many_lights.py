#!/usr/bin/env python3
"""Writes the many-lights scenes.

    scripts/make_many_lights.py [OUT.json]     assets/scenes/many_lights.json (the default): a floor
                                               with a few objects under a 16 x 16 grid of small ceiling
                                               lights of very different power (256 emitters), the scene
                                               used to compare `--light-selection all` with `power`
    scripts/make_many_lights.py --obj OUT.obj  OUT.obj and OUT.mtl beside it: a floor with boxes under a
                                               32 x 32 grid of small emissive quads (1,024 emitters, each
                                               its own object, so one light each) in 16 radiance levels
                                               over three orders of magnitude, all Lambert, for renderers
                                               that read OBJ (scripts/bench_cycles.py)
"""
import json
import math
import sys
from pathlib import Path


def radiance_level(i, j, levels=16):
    """Which of the levels a grid cell gets: spread over the grid without a visible pattern."""
    return (i * 7 + j * 13) % levels


def json_scene():
    lights = []
    for i in range(16):
        for j in range(16):
            # Power varies over three orders of magnitude across the grid.
            le = 0.5 * math.exp(radiance_level(i, j) / 15.0 * math.log(1000.0))
            lights.append({
                "type": "rectangle",
                "p0": [-8 + i, 6, -8 + j + 0.25],
                "a": [0.5, 0, 0],
                "b": [0, 0, 0.5],
                "radiance": round(le / 100.0, 4),
            })
    # cross(a, b) = (0.5,0,0) x (0,0,0.5) = (0, -0.25, 0): every light faces down.
    return {
        "camera": {"eye": [0, 4, 14], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov": 45},
        "render": {"width": 320, "height": 240, "spp": 4, "light_samples": 1, "seed": 1},
        "materials": {
            "floor": {"kd": 0.7},
            "red": {"kd": [0.7, 0.2, 0.1], "ks": 0.2, "n": 30},
            "blue": {"kd": [0.1, 0.3, 0.7]},
        },
        "shapes": [
            {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
            {"type": "sphere", "center": [-2, 1, 0], "radius": 1, "material": "red"},
            {"type": "box", "min": [1, 0, -1], "max": [3, 2, 1], "material": "blue"},
        ],
        "lights": lights,
    }


# (min corner, max corner, material) of the OBJ scene's boxes.
BOXES = [
    ((1, 0, -1), (3, 2, 1), "blue"),
    ((-3, 0, -1.5), (-1.5, 1.5, 0), "red"),
    ((-0.5, 0, 2), (0.5, 3, 3), "white"),
    ((3.5, 0, 3), (4.5, 1, 4), "white"),
    ((-5, 0, -5), (-3, 4, -3), "blue"),
]
MATERIALS = {"floor": (0.7, 0.7, 0.7), "white": (0.75, 0.75, 0.75), "red": (0.7, 0.2, 0.1), "blue": (0.1, 0.3, 0.7)}


def box_faces(lo, hi):
    """The six faces of an axis-aligned box as counter-clockwise quads seen from outside."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    return [
        [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],  # top, +y
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],  # front, +z
        [(x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0)],  # back, -z
        [(x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1)],  # +x
        [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],  # -x
    ]


def write_obj(obj_path):
    """The OBJ scene: a 20 x 20 floor, five boxes, and 1,024 quads of 0.2 x 0.2 at y = 5 facing
    down, every 0.5 over [-8, 8) x [-8, 8), of radiance 0.01 to 10 (16 levels, each 1000^(1/15)
    times the last)."""
    obj_path = Path(obj_path)
    mtl_path = obj_path.with_suffix(".mtl")
    obj_path.parent.mkdir(parents=True, exist_ok=True)
    out = [f"# {obj_path.name}: written by scripts/make_many_lights.py --obj", f"mtllib {mtl_path.name}"]
    count = 0

    def quad(corners):
        nonlocal count
        out.extend("v {:g} {:g} {:g}".format(*c) for c in corners)
        count += 4
        out.append(f"f {count - 3} {count - 2} {count - 1} {count}")

    out += ["o floor", "usemtl floor"]
    quad([(-10, 0, -10), (-10, 0, 10), (10, 0, 10), (10, 0, -10)])
    for n, (lo, hi, material) in enumerate(BOXES):
        out += [f"o box_{n}", f"usemtl {material}"]
        for face in box_faces(lo, hi):
            quad(face)
    for i in range(32):
        for j in range(32):
            x, z = -8 + 0.5 * i + 0.15, -8 + 0.5 * j + 0.15
            out += [f"o light_{i:02d}_{j:02d}", f"usemtl light_{radiance_level(i, j):02d}"]
            # Counter-clockwise seen from below: the front, the emitting side, faces -y.
            quad([(x, 5, z), (x + 0.2, 5, z), (x + 0.2, 5, z + 0.2), (x, 5, z + 0.2)])
    obj_path.write_text("\n".join(out) + "\n")
    mtl = []
    for name, kd in MATERIALS.items():
        mtl += [f"newmtl {name}", "Kd {:g} {:g} {:g}".format(*kd), "Ks 0 0 0", "illum 2", ""]
    for level in range(16):
        le = 0.01 * 1000.0 ** (level / 15.0)
        mtl += [f"newmtl light_{level:02d}", "Kd 0 0 0", "Ks 0 0 0", f"Ke {le:.6g} {le:.6g} {le:.6g}", "illum 2", ""]
    mtl_path.write_text("\n".join(mtl))


def main():
    args = sys.argv[1:]
    if args[:1] == ["--obj"]:
        if len(args) != 2:
            sys.exit("usage: make_many_lights.py --obj OUT.obj")
        write_obj(args[1])
        return
    out = args[0] if args else "assets/scenes/many_lights.json"
    with open(out, "w") as f:
        json.dump(json_scene(), f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()

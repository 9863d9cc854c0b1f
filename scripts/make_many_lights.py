#!/usr/bin/env python3
"""Many-light scenes.

  scripts/make_many_lights.py [OUT.json]
      assets/scenes/many_lights.json: a floor with a few objects under a 16 x 16
      grid of small ceiling lights (JSON rectangles) of very different power
      (256 emitters), the scene used to compare `--light-selection all` with
      `power` in docs/rendering.md.

  scripts/make_many_lights.py --obj DIR [--grid K | --grid KxM]
      DIR/many_lights.obj, .mtl and .json: the scene of the many-lights
      benchmark (scripts/bench_many_lights.py): an OBJ floor with boxes under a
      K x K (or K x M) grid (default 32: 1,024 lights) of small emissive quads
      facing down over the same 32 x 32 area, each its own material, radiance
      spread over three orders of magnitude; the JSON places the camera and
      renders 160x120, 4 spp, with the path integrator. The same grid always
      gives the same files. --merged writes the quads instead as one object of
      one material of their mean radiance (one light of many triangles, as an
      emissive mesh is), --uniform gives every quad that radiance: the pair
      measures what lights of single primitives gain the light hierarchy.
"""
import argparse
import json
import math
from pathlib import Path


def json_scene(out):
    lights = []
    for i in range(16):
        for j in range(16):
            # Power varies over three orders of magnitude across the grid.
            le = 0.5 * math.exp(((i * 7 + j * 13) % 16) / 15.0 * math.log(1000.0))
            lights.append({
                "type": "rectangle",
                "p0": [-8 + i, 6, -8 + j + 0.25],
                "a": [0.5, 0, 0],
                "b": [0, 0, 0.5],
                "radiance": round(le / 100.0, 4),
            })
    # cross(a, b) = (0.5,0,0) x (0,0,0.5) = (0, -0.25, 0): every light faces down.
    scene = {
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
    with open(out, "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


def obj_scene(folder, kx, kz, merged=False, uniform=False):
    """The kx x kz-light OBJ scene in folder (see the module's doc)."""
    folder.mkdir(parents=True, exist_ok=True)
    half = 16.0  # the grid spans [-half, half] in x and z
    sx, sz = 2 * half / kx, 2 * half / kz  # one light per cell, at its centre
    v, faces, mtl = [], [], []

    def quad(corners, material, name):
        base = len(v) + 1
        v.extend(corners)
        faces.append(f"o {name}\nusemtl {material}\nf {base} {base + 1} {base + 2} {base + 3}")

    def box(lo, hi, material, name):
        x0, y0, z0 = lo
        x1, y1, z1 = hi
        c = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
             (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
        base = len(v) + 1
        v.extend(c)
        # Counter-clockwise seen from outside.
        sides = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 4, 7, 3), (1, 2, 6, 5), (3, 7, 6, 2), (0, 1, 5, 4)]
        faces.append(f"o {name}\nusemtl {material}\n" +
                     "\n".join("f " + " ".join(str(base + i) for i in s) for s in sides))

    mtl.append("newmtl floor\nKd 0.7 0.7 0.7\n")
    mtl.append("newmtl crate\nKd 0.6 0.45 0.3\n")
    mtl.append("newmtl slate\nKd 0.25 0.3 0.4\n")
    size = half + 4.0
    quad([(-size, 0, size), (size, 0, size), (size, 0, -size), (-size, 0, -size)], "floor", "floor")
    # Boxes of a few sizes on a loose grid (a fixed pattern, not random).
    n = 0
    for i in range(-2, 3):
        for j in range(-2, 3):
            if (i * 3 + j * 5) % 3 == 0:
                continue
            cx, cz = i * half / 2.6 + 0.7 * j, j * half / 2.6 - 0.4 * i
            w = 0.6 + 0.25 * ((i * 7 + j * 11) % 4)
            h = 0.8 + 0.6 * ((i * 5 + j * 3) % 5)
            box((cx - w, 0, cz - w), (cx + w, h, cz + w), "crate" if (i + j) % 2 else "slate", f"box{n}")
            n += 1
    # The lights: 0.25 x 0.25 quads at y = 6, facing down, radiance 0.05 to 50.
    radiance = {(i, j): 0.05 * 1000.0 ** (((i * 37 + j * 61 + (i * j) % 17) % 101) / 100.0)
                for i in range(kx) for j in range(kz)}
    mean = sum(radiance.values()) / len(radiance)
    if merged:
        mtl.append(f"newmtl lights\nKd 0 0 0\nKe {mean:.5g} {mean:.5g} {mean:.5g}\n")
        faces.append("o lights\nusemtl lights")
    for i in range(kx):
        for j in range(kz):
            le = mean if uniform else radiance[(i, j)]
            name = f"light{i:02d}_{j:02d}"
            x, z = -half + (i + 0.5) * sx - 0.125, -half + (j + 0.5) * sz - 0.125
            corners = [(x, 6, z), (x + 0.25, 6, z), (x + 0.25, 6, z + 0.25), (x, 6, z + 0.25)]
            if merged:
                base = len(v) + 1
                v.extend(corners)
                faces.append(f"f {base} {base + 1} {base + 2} {base + 3}")
                continue
            mtl.append(f"newmtl {name}\nKd 0 0 0\nKe {le:.5g} {le:.5g} {le:.5g}\n")
            quad(corners, name, name)
    with open(folder / "many_lights.mtl", "w") as f:
        f.write("# Written by scripts/make_many_lights.py --obj\n" + "\n".join(mtl))
    with open(folder / "many_lights.obj", "w") as f:
        f.write("# Written by scripts/make_many_lights.py --obj: a floor, boxes and "
                f"{kx * kz} emissive quads facing down\nmtllib many_lights.mtl\n")
        f.write("".join(f"v {x:g} {y:g} {z:g}\n" for x, y, z in v))
        f.write("\n".join(faces) + "\n")
    scene = {
        # Looking down at the floor and boxes, the lights just out of view (the top
        # row of pixels looks level, below them): pixels that see a small bright
        # quad would add the same antialiasing noise to every light selection.
        "camera": {"eye": [0, 5.5, half + 6], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 28},
        "render": {"width": 160, "height": 120, "spp": 4, "seed": 1, "integrator": "path"},
        "shapes": [{"type": "mesh", "file": "many_lights.obj"}],
    }
    with open(folder / "many_lights.json", "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", nargs="?", default="assets/scenes/many_lights.json", help="the JSON scene (without --obj)")
    ap.add_argument("--obj", type=Path, help="write the OBJ scene into this folder instead")
    ap.add_argument("--grid", default="32", help="the OBJ scene's lights: K (K x K, default 32) or KxM")
    ap.add_argument("--merged", action="store_true", help="the OBJ scene's quads as one light of their mean radiance")
    ap.add_argument("--uniform", action="store_true", help="every quad of the OBJ scene at the mean radiance")
    a = ap.parse_args()
    if a.obj:
        kx, _, kz = a.grid.partition("x")
        obj_scene(a.obj, int(kx), int(kz or kx), a.merged, a.uniform)
    else:
        json_scene(a.out)


if __name__ == "__main__":
    main()

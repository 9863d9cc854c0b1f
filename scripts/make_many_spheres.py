#!/usr/bin/env python3
"""Writes a JSON scene with N small spheres in a cube grid (and, with
--materials, one material of its own per sphere), the input that measures the
JSON loader's cost per element (docs/benchmarks.md, "JSON loading").
  usage: scripts/make_many_spheres.py N OUT.json [--materials]"""
import sys


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    n = int(sys.argv[1])
    out = sys.argv[2]
    own_materials = "--materials" in sys.argv[3:]
    side = max(1, round(n ** (1 / 3)) + 1)
    with open(out, "w") as f:
        f.write('{\n"camera": {"eye": [0, 0, %d], "look_at": [0, 0, 0], "fov": 60},\n' % (3 * side))
        f.write('"render": {"width": 32, "height": 32, "spp": 1, "seed": 1},\n')
        f.write('"lights": [{"type": "point", "position": [0, %d, %d], "intensity": %d}],\n' % (2 * side, 2 * side, side * side))
        f.write('"materials": {"grey": {"kd": 0.7}')
        if own_materials:
            for i in range(n):
                f.write(',\n "m%d": {"kd": [%.3f, 0.5, 0.5]}' % (i, (i % 1000) / 1000))
        f.write('},\n"shapes": [\n')
        for i in range(n):
            x, y, z = i % side - side / 2, (i // side) % side - side / 2, i // (side * side) - side / 2
            mat = "m%d" % i if own_materials else "grey"
            f.write('%s{"type": "sphere", "center": [%g, %g, %g], "radius": 0.3, "material": "%s"}' %
                    (",\n" if i else "", x, y, z, mat))
        f.write("\n]\n}\n")


if __name__ == "__main__":
    main()

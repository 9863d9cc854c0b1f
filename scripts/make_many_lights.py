#!/usr/bin/env python3
"""Writes assets/scenes/many_lights.json: a floor with a few objects under a
16 x 16 grid of small ceiling lights of very different power (256 emitters),
the scene used to compare `--light-selection all` with `power`."""
import json
import math
import sys

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
out = sys.argv[1] if len(sys.argv) > 1 else "assets/scenes/many_lights.json"
with open(out, "w") as f:
    json.dump(scene, f, indent=1)
    f.write("\n")

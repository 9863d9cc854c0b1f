#!/usr/bin/env python3
"""Where a Whitted render's time goes by kind of ray: renders a JSON scene four
ways, alternating, and prints each way's median render time and ray counts:

    as is
    --max-depth 0                  (no mirror or glass rays)
    the lights removed             (no shadow rays)
    the lights removed, --max-depth 0

From the differences it prints the cost of a camera sample (with its query,
hit completion, shading and film), of a mirror/transmitted ray and of a shadow
ray (each with its query and the shading it brings). The cost of a kind is an
average over that scene's rays, not a per-ray measurement. Scenes whose light
comes also from emissive surfaces or an environment are refused: without the
lights they still trace shadow rays.

    scripts/ray_kind_costs.py [--penumbra BIN] [--runs N] SCENE.json [-- OPTIONS...]

OPTIONS go to every render (for example --threads 1). The lights-removed scene
is a copy of SCENE.json with "lights": [] in a temporary folder that holds
every other file of the scene's folder (hard links, else copies; not symbolic
links, which the path policy would count as outside the folder), so relative
paths still resolve.
"""
import argparse
import datetime
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile


def strip_comments(text):
    """The scene without its // and /* */ comments (which the scene format
    allows outside strings): the lights-removed copy is plain JSON."""
    out, i, n, in_string = [], 0, len(text), False
    while i < n:
        c = text[i]
        if in_string:
            out.append(c)
            if c == "\\" and i + 1 < n:
                out.append(text[i + 1])
                i += 1
            elif c == '"':
                in_string = False
        elif c == '"':
            in_string = True
            out.append(c)
        elif text.startswith("//", i):
            i = text.find("\n", i)
            if i < 0:
                break
            continue
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            i = n if end < 0 else end + 2
            continue
        else:
            out.append(c)
        i += 1
    return "".join(out)


def render(binary, scene, options, stats_path):
    cmd = [binary, scene, "-q", "-o", os.path.join(os.path.dirname(stats_path), "image.pfm"),
           "--stats-json", stats_path] + options
    subprocess.run(cmd, check=True)
    with open(stats_path) as f:
        return json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--penumbra", default=os.path.join(os.path.dirname(__file__), "..", "build", "bin", "penumbra"))
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("scene")
    parser.add_argument("options", nargs=argparse.REMAINDER)
    args = parser.parse_args()
    options = [o for o in args.options if o != "--"]
    scene = os.path.abspath(args.scene)
    try:
        with open(scene) as f:
            document = json.loads(strip_comments(f.read()))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        sys.exit(f"{args.scene}: not a readable JSON scene ({e})")
    if not document.get("lights"):
        sys.exit(f"{args.scene}: the scene has no lights to remove")

    with tempfile.TemporaryDirectory() as tmp:
        folder = os.path.dirname(scene)
        for root, _, files in os.walk(folder):
            into = os.path.join(tmp, os.path.relpath(root, folder))
            os.makedirs(into, exist_ok=True)
            for name in files:
                source = os.path.join(root, name)
                if source == scene:
                    continue
                try:
                    os.link(source, os.path.join(into, name))
                except OSError:
                    shutil.copy2(source, os.path.join(into, name))
        unlit = os.path.join(tmp, os.path.basename(scene))
        document["lights"] = []
        with open(unlit, "w") as f:
            json.dump(document, f)
        ways = [("as is", scene, []), ("--max-depth 0", scene, ["--max-depth", "0"]),
                ("lights removed", unlit, []), ("lights removed, --max-depth 0", unlit, ["--max-depth", "0"])]
        seconds = {w[0]: [] for w in ways}
        rays = {}
        stats_path = os.path.join(tmp, "stats.json")
        for r in range(args.runs):
            for label, path, extra in ways if r % 2 == 0 else reversed(ways):
                s = render(args.penumbra, path, options + extra, stats_path)
                seconds[label].append(s["render_seconds"])
                rays[label] = s["rays"]

    print(f"date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC")
    print(f"command: {' '.join(sys.argv)}")
    print(f"{'way':32} {'render ms':>10} {'camera':>10} {'mirror+glass':>13} {'shadow':>10}")
    med = {}
    for label, _, _ in ways:
        med[label] = statistics.median(seconds[label])
        k = rays[label]
        print(f"{label:32} {med[label] * 1e3:10.1f} {k['camera']:10d} {k['reflection'] + k['transmission']:13d} "
              f"{k['shadow']:10d}")
    base = "lights removed, --max-depth 0"
    if rays["lights removed"]["shadow"] or rays[base]["shadow"]:
        sys.exit("the renders without the scene's lights still trace shadow rays (emissive surfaces, an "
                 "environment or a default light): the kinds of ray cannot be told apart in this scene")
    camera = rays[base]["camera"]
    bounced = rays["lights removed"]["reflection"] + rays["lights removed"]["transmission"]
    shadow = rays["as is"]["shadow"]
    print(f"camera sample: {med[base] / camera * 1e9:.1f} ns")
    if bounced:
        print(f"mirror/transmitted ray: {(med['lights removed'] - med[base]) / bounced * 1e9:.1f} ns")
    if shadow:
        print(f"shadow ray: {(med['as is'] - med['lights removed']) / shadow * 1e9:.1f} ns")


if __name__ == "__main__":
    main()

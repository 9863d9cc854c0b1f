#!/usr/bin/env python3
"""Renders a model with Penumbra and with Blender's Cycles at the same camera, size and environment,
and prints how far apart the two images are.

    scripts/compare_blender.py MODEL [--out DIR] [--width W] [--height H] [--spp N] [--env r,g,b|FILE]
                               [--env-rotate DEG] [--exposure STOPS] [--max-depth D] [--threads N]
                               [--penumbra BUILD_DIR]
    scripts/compare_blender.py --gallery [MODEL ...] [same options; --out defaults to docs/gallery/cycles]

MODEL is a glTF/GLB file (read by Khronos' importer in Blender, onto the
Principled BSDF) or OBJ/MTL (Blender's OBJ importer). Each renderer keeps its own reading of the
materials: this compares what a user gets. Installs Debian's `blender` when missing (as root).

Cycles renders first (scripts/blender_render.py): it uses the model's first perspective camera, or
frames the model's bounding box from a raised three-quarter view (30 degrees round from +z towards
+x, 20 degrees up, 40 degrees vertical field of view, the bounding sphere filling the frame), and
reports that camera; Penumbra then gets it explicitly (--eye --look-at --up --fov), so both see the
same view. Both path trace (Penumbra `--integrator path --max-depth D`, Cycles max bounces D - 1, box
pixel filter, no denoising, no adaptive sampling, no clamping) under the same environment
(default a constant 1,1,1; a lat-long image is mapped as Penumbra maps --env, nearest texel).

Writes MODEL.penumbra.png, MODEL.cycles.png and MODEL.side.png (Penumbra left) into --out, all made
here from the linear images with one display transform (2^exposure, the sRGB curve, clamped, 8-bit),
and prints the mean absolute difference of those display values (0-255, over pixels and channels)
and each image's linear per-channel means. --gallery does a list (default: every model in
../shared/scenes/khronos_gltf, FlightHelmet, McGuire's pine) and writes README.md in --out with both
images side by side and the command beside each.
"""
import argparse
import datetime
import json
import os
import shlex
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import blender_common as bc  # noqa: E402

TOOL = "compare_blender.py"
FRAME = {"azimuth": 30.0, "elevation": 20.0, "fov": 40.0}


def gallery_models():
    models = []
    khronos = bc.SHARED / "scenes" / "khronos_gltf"
    for folder in sorted(khronos.iterdir()) if khronos.is_dir() else []:
        found = sorted(folder.glob("glTF-Binary/*.glb")) or sorted(folder.glob("glTF/*.gltf"))
        if found:
            models.append(found[0])
    for extra in ("flighthelmet_bevy/FlightHelmet.gltf", "pine_mcguire/scrubPine.obj"):
        if (bc.SHARED / "scenes" / extra).exists():
            models.append(bc.SHARED / "scenes" / extra)
    return models


def parse_environment(text, rotate):
    parts = text.split(",")
    if len(parts) == 3:
        try:
            return {"rgb": [float(p) for p in parts]}
        except ValueError:
            pass
    if not Path(text).is_file():
        raise ValueError(f"--env {text}: neither r,g,b nor an image file")
    return {"file": str(Path(text).resolve()), "rotate": rotate}


def side_by_side(left, right, width, height):
    out = bytearray()
    for y in range(height):
        out += left[y * width * 3:(y + 1) * width * 3] + right[y * width * 3:(y + 1) * width * 3]
    return out


def mean_abs_difference(a, b):
    return sum(abs(x - y) for x, y in zip(a, b)) / len(a)


def compare(model, args, env, workdir):
    """Renders one model both ways; writes the PNGs; returns the figures."""
    model = Path(os.path.abspath(model))  # not resolved: ../shared stays ../shared in the commands shown
    workdir = Path(workdir)
    stem = model.stem
    cycles_pfm, penumbra_pfm = workdir / f"{stem}.cycles.pfm", workdir / f"{stem}.penumbra.pfm"
    job = {"scene": str(model), "materials": "native", "camera": "scene", "frame": FRAME, "environment": env,
           "width": args.width, "height": args.height, "spp": args.spp, "max_bounces": args.max_depth - 1,
           "seed": 1, "threads": args.threads, "output": str(cycles_pfm)}
    report = bc.run_cycles(TOOL, job, workdir)
    options = ["--integrator", "path", "--max-depth", str(args.max_depth), "--spp", str(args.spp),
               "--width", str(args.width), "--height", str(args.height), "--seed", "1",
               "--threads", str(args.threads)] + bc.camera_options(report["camera"]) + bc.environment_options(env)
    stats = bc.run_penumbra(TOOL, args.penumbra, model, options, penumbra_pfm, workdir / "stats.json")
    pen, cyc = bc.read_pfm(penumbra_pfm), bc.read_pfm(cycles_pfm)
    pen8, cyc8 = bc.srgb8(pen, args.exposure), bc.srgb8(cyc, args.exposure)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    bc.write_png(out / f"{stem}.penumbra.png", args.width, args.height, pen8)
    bc.write_png(out / f"{stem}.cycles.png", args.width, args.height, cyc8)
    if not args.gallery:
        bc.write_png(out / f"{stem}.side.png", 2 * args.width, args.height,
                     side_by_side(pen8, cyc8, args.width, args.height))
    return {"model": str(model), "name": stem, "camera": report["camera"],
            "camera_source": report.get("camera_source", ""),
            "mean_abs_difference": mean_abs_difference(pen8, cyc8),
            "penumbra_means": pen.channel_means(), "cycles_means": cyc.channel_means(),
            "penumbra_seconds": bc.penumbra_seconds(stats), "cycles_seconds": report["render_seconds"],
            "penumbra_command": shlex.join(["penumbra", display_path(model), *options, "-o", f"{stem}.exr"])}


def display_path(path):
    """A path as the commands in the gallery show it: relative to the repository where it can be."""
    try:
        return os.path.relpath(path, bc.ROOT)
    except ValueError:
        return str(path)


def print_result(r):
    print(f"{r['name']}: camera {r['camera_source'] or 'given'}; mean absolute difference of display values "
          f"{r['mean_abs_difference']:.2f} / 255", flush=True)
    print("  linear means  Penumbra " + " ".join(f"{x:.4f}" for x in r["penumbra_means"])
          + "   Cycles " + " ".join(f"{x:.4f}" for x in r["cycles_means"]), flush=True)
    print(f"  render seconds (preparation + sampling): Penumbra {r['penumbra_seconds']:.2f}, "
          f"Cycles {r['cycles_seconds']:.2f}", flush=True)


def write_index(args, results, env_text):
    out = Path(args.out)
    commit = subprocess.run(["git", "-C", str(bc.ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip() or "unknown"
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "unknown")
    common = (f"--width {args.width} --height {args.height} --spp {args.spp} --max-depth {args.max_depth} "
              f"--env {env_text}" + (f" --env-rotate {args.env_rotate:g}" if args.env_rotate else "")
              + (f" --exposure {args.exposure:g}" if args.exposure else ""))
    lines = [
        "# Gallery: Penumbra and Blender Cycles side by side", "",
        f"Generated by `scripts/compare_blender.py --gallery --out {display_path(out)} {common}` at commit "
        f"{commit}, Blender {bc.blender_version()}, on {cpu}, "
        f"{datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d')}.",
        "Both path trace the model as each renderer reads it (Cycles: Blender's own importer, glTF onto the "
        "Principled BSDF) with the same camera (the model's, or the same framing), size, samples, path length "
        "and environment; both images pass through one display transform (sRGB, 8-bit). "
        "*MAD*: mean absolute difference of those display values, 0-255. Do not edit by hand; rerun the command.",
        "", "| model | Penumbra | Cycles | MAD | command |", "| --- | --- | --- | --- | --- |"]
    for r in results:
        one = f"scripts/compare_blender.py {display_path(r['model'])} --out {display_path(out)} {common}"
        lines.append(f"| {r['name']} | ![{r['name']} Penumbra]({r['name']}.penumbra.png) | "
                     f"![{r['name']} Cycles]({r['name']}.cycles.png) | {r['mean_abs_difference']:.1f} | "
                     f"`{one}`<br>Penumbra: `{r['penumbra_command']}` |")
    (out / "README.md").write_text("\n".join(lines) + "\n")
    print(f"wrote {out / 'README.md'}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("models", nargs="*", help="models to compare (with --gallery: default the gallery's list)")
    ap.add_argument("--gallery", action="store_true", help="a list of models and an index page")
    ap.add_argument("--out", help="output folder (default: . ; with --gallery docs/gallery/cycles)")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--env", default="1,1,1", help="r,g,b or a lat-long image (default 1,1,1)")
    ap.add_argument("--env-rotate", type=float, default=0.0)
    ap.add_argument("--exposure", type=float, default=0.0, help="stops, for the display values")
    ap.add_argument("--max-depth", type=int, default=10, help="Penumbra's path length (Cycles: one bounce less)")
    ap.add_argument("--threads", type=int, default=0, help="threads of each renderer (0: all cores)")
    ap.add_argument("--penumbra", default=str(bc.ROOT / "build"), help="build folder with bin/penumbra and lib/")
    ap.add_argument("--json", help="write the figures here")
    args = ap.parse_args()
    size = 256 if args.gallery else 512
    args.width, args.height = args.width or size, args.height or size
    args.out = args.out or (str(bc.ROOT / "docs" / "gallery" / "cycles") if args.gallery else ".")
    models = [Path(m) for m in args.models] or (gallery_models() if args.gallery else [])
    if not models:
        ap.error("give a model (or --gallery)")
    missing = [str(m) for m in models if not m.is_file()]
    if missing:
        ap.error("no such file: " + ", ".join(missing))
    other = [str(m) for m in models if m.suffix.lower() not in (".gltf", ".glb", ".obj")]
    if other:
        ap.error("only glTF, GLB and OBJ models are compared: " + ", ".join(other))
    if min(args.width, args.height, args.spp, args.max_depth) < 1 or args.threads < 0:
        ap.error("--width, --height, --spp and --max-depth must be at least 1, --threads at least 0")
    try:
        env = parse_environment(args.env, args.env_rotate)
    except ValueError as e:
        ap.error(str(e))
    if args.env_rotate and "file" not in env:
        ap.error("--env-rotate needs --env FILE")
    if bc.penumbra_exe(args.penumbra) is None:
        bc.fail(TOOL, f"{args.penumbra}/bin/penumbra: no penumbra executable (--penumbra BUILD_DIR)")
    bc.ensure_blender(TOOL)
    results = []
    with bc.temp_dir("compare_blender.") as tmp:
        for model in models:
            r = compare(model, args, env, tmp)
            print_result(r)
            results.append(r)
    if args.gallery:
        write_index(args, results, args.env if "rgb" in env else display_path(env["file"]))
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()

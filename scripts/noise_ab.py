#!/usr/bin/env python3
"""Noise per sample of two Penumbra builds on scripts/bench_cycles.py's scenes, at equal samples.

    scripts/noise_ab.py OLD_BUILD NEW_BUILD [--scenes a,b,...] [--seeds N] [--threads N]
                        [--cache DIR] [--ref-factor K] [--max-depth D]

Each scene is rendered as bench_cycles.py renders it for Penumbra (the same Lambert copy, camera,
size, samples and options), by both builds, with seeds 1 .. N, interleaved (OLD first for odd seeds,
NEW first for even ones). relMSE is taken against bench_cycles.py's cached Penumbra reference (made
by OLD_BUILD when absent), times K / (K + 1) as there. Prints per scene the mean relMSE of each build,
the ratio OLD / NEW (above 1: NEW has less noise per sample), the spread of the per-seed ratios, and
the median render times (indicative only on a loaded machine). relMSE at equal samples does not
depend on the machine's load.
"""
import argparse
import os
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_cycles as bcy  # noqa: E402
import blender_common as bc  # noqa: E402

TOOL = "noise_ab.py"


def main():
    sys.stdout.reconfigure(line_buffering=True)
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    names = [s.name for s in bcy.SCENES]
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--scenes", default=",".join(names), help="comma-separated, of: " + ", ".join(names))
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--cache", default=os.path.join(os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")),
                                                     "penumbra", "bench_cycles"))
    ap.add_argument("--ref-factor", type=int, default=16)
    ap.add_argument("--max-depth", type=int, default=10)
    args = ap.parse_args()
    for build in (args.old, args.new):
        if bc.penumbra_exe(build) is None:
            bc.fail(TOOL, f"{build}/bin/penumbra: no penumbra executable")
    wanted = [n.strip() for n in args.scenes.split(",") if n.strip()]
    if any(n not in names for n in wanted) or args.seeds < 1:
        ap.error(f"--scenes takes names of {', '.join(names)}; --seeds at least 1")
    # bench_cycles.Bench renders the reference with its --penumbra build: OLD's.
    bench = bcy.Bench(argparse.Namespace(penumbra=args.old, cache=args.cache, max_depth=args.max_depth, scale=1.0,
                                         spp_scale=1.0, ref_factor=args.ref_factor))
    builds = {"old": args.old, "new": args.new}
    print(f"old: {args.old} (build {bc.build_fingerprint(args.old)})\nnew: {args.new} "
          f"(build {bc.build_fingerprint(args.new)})\ncommand: scripts/{TOOL} {' '.join(sys.argv[1:])}")
    correction = args.ref_factor / (args.ref_factor + 1)
    with bc.temp_dir("noise_ab.") as tmp:
        tmp = Path(tmp)
        for scene in bcy.SCENES:
            if scene.name not in wanted:
                continue
            prepared = bench.prepare(scene)
            if prepared is None:
                print(f"{scene.name}: skipped ({scene.source} is absent)")
                continue
            size = bench.settings(scene)
            spp = size.pop("spp")
            ref, _ = bench.reference(scene, prepared, "penumbra", size, spp * args.ref_factor, tmp)
            runs = {"old": [], "new": []}
            for seed in range(1, args.seeds + 1):
                for which in (("old", "new") if seed % 2 else ("new", "old")):
                    bench.build = Path(builds[which])
                    out = tmp / f"{which}.pfm"
                    run = bench.penumbra(scene, prepared, size, spp, seed, args.threads, out, tmp)
                    runs[which].append((bc.rel_mse(bc.read_pfm(out), ref) * correction, run["seconds"]))
            bench.build = Path(args.old)
            mean = {w: statistics.fmean(r[0] for r in rs) for w, rs in runs.items()}
            ratios = [o[0] / n[0] for o, n in zip(runs["old"], runs["new"])]
            secs = {w: statistics.median(r[1] for r in rs) for w, rs in runs.items()}
            print(f"{scene.name} ({size['width']}x{size['height']}, {spp} spp, {args.seeds} seeds): relMSE old "
                  f"{mean['old']:.4g}, new {mean['new']:.4g}, old/new {mean['old'] / mean['new']:.3f} "
                  f"(per seed {min(ratios):.3f} .. {max(ratios):.3f}); seconds old {secs['old']:.2f}, "
                  f"new {secs['new']:.2f}")


if __name__ == "__main__":
    main()

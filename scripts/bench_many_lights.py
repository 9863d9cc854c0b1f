#!/usr/bin/env python3
"""Many-lights benchmark: noise, time and efficiency of each --light-selection.

The scene is scripts/make_many_lights.py --obj (an OBJ floor with boxes under a
grid of small emissive quads facing down, radiance over three orders of
magnitude; 1,024 lights by default), rendered at the scene's 160x120 and 4 spp.
For each integrator and light selection the script renders --rounds times
(seeds 1, 2, ...; the selections interleaved, their order alternating between
rounds, so a loaded machine slows all alike) and reports the median
render_seconds of --stats-json, the mean relative MSE against a converged
reference (mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01),
scripts/bench_noise.py's measure) and the efficiency 1 / (relMSE x time),
also as a ratio to `all`, the default before `auto`. The reference is the
tree at --ref-spp camera samples with another seed (its own noise, about
1/(ref-spp/4) of the tree's at 4 spp, is counted in every relMSE alike); it is
cached under build/bench_many_lights/ by scene, integrator and spp.

--old DIR adds today's default from another build (DIR/bin/penumbra with
DIR/lib), e.g. /work/baseline. --sweep "1x1 2x1 ..." instead compares `all`
and `tree` on scenes of fewer lights (grids over the same area), the measure
behind `auto`'s threshold (lights/light_selection.h). --granularity instead
compares the quads at one radiance as lights of their own (make_many_lights.py
--uniform) with the same quads as one mesh light (--merged), each under its
default selection: what leaves of single primitives gain the tree.

  scripts/bench_many_lights.py [--build build] [--old DIR] [--grid 32] [--rounds 3]
                               [--integrators path,whitted] [--selections all,power,tree,auto]
                               [--ref-spp 1024] [--threads 2] [--sweep GRIDS | --granularity]
                               [--out FILE]
"""
import argparse
import hashlib
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from ab_builds import cpu_model  # noqa: E402
from bench_noise import read_pfm, rel_mse  # noqa: E402


def make_scene(folder, grid, *variant):
    """make_many_lights.py --obj's scene in folder; variant: its extra options (--merged, --uniform)."""
    subprocess.run([sys.executable, str(ROOT / "scripts/make_many_lights.py"), "--obj", str(folder), "--grid", grid,
                    *variant], check=True)
    return folder / "many_lights.json"


def render(build, scene, out, options, threads):
    """Renders scene with build (a folder holding bin/penumbra and lib/); returns --stats-json's figures."""
    stats = out.with_suffix(".json")
    env = dict(os.environ, LD_LIBRARY_PATH=str(Path(build) / "lib"))
    cmd = [str(Path(build) / "bin/penumbra"), str(scene), "-o", str(out), "-q", "--threads", str(threads),
           "--stats-json", str(stats)] + options
    p = subprocess.run(cmd, env=env, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit(f"bench_many_lights: {' '.join(cmd)} failed:\n{p.stderr}")
    return json.loads(stats.read_text())


def reference(build, scene, integrator, spp, threads):
    """The converged image of scene (cached by the scene's bytes, integrator and spp)."""
    digest = hashlib.sha256()
    for f in sorted(scene.parent.iterdir()):
        digest.update(f.name.encode() + f.read_bytes())
    cache = ROOT / "build/bench_many_lights"
    cache.mkdir(parents=True, exist_ok=True)
    path = cache / f"ref_{digest.hexdigest()[:16]}_{integrator}_{spp}.pfm"
    if not path.exists():
        tmp = path.with_name("tmp_" + path.name)
        st = render(build, scene, tmp, ["--integrator", integrator, "--light-selection", "tree", "--spp", str(spp),
                                        "--seed", "1000"], threads)
        print(f"  reference {integrator}, {spp} spp: {st['render_seconds']:.1f} s", flush=True)
        tmp.rename(path)
    return read_pfm(path)


def compare(configs, integrator, ref, rounds, threads, tmp):
    """Renders every (label, build, scene, options) config `rounds` times, interleaved;
    returns {label: (median seconds, mean relMSE, shadow rays of round 1)}."""
    times, errors, shadow = {}, {}, {}
    for r in range(rounds):
        order = configs if r % 2 == 0 else configs[::-1]
        for label, build, scene, options in order:
            out = tmp / f"img_{len(times.get(label, []))}_{abs(hash(label))}.pfm"
            st = render(build, scene, out, ["--integrator", integrator, "--seed", str(r + 1)] + options, threads)
            times.setdefault(label, []).append(st["render_seconds"])
            errors.setdefault(label, []).append(rel_mse(read_pfm(out), ref))
            shadow.setdefault(label, st["rays"]["shadow"])
    return {label: (statistics.median(times[label]), statistics.fmean(errors[label]), shadow[label])
            for label, _, _, _ in configs}


def table(say, results, base):
    say(f"  {'selection':<24} {'time s':>8} {'relMSE':>10} {'efficiency':>10} {'vs ' + base:>8} {'shadow rays':>12}")
    eff_base = 1.0 / (results[base][0] * results[base][1])
    for label, (t, e, rays) in results.items():
        eff = 1.0 / (t * e)
        say(f"  {label:<24} {t:>8.3f} {e:>10.3e} {eff:>10.1f} {eff / eff_base:>8.2f} {rays:>12}")


def selections(a, say, tmp):
    """The selections (or with --sweep, all and tree) on each grid's scene."""
    for grid in a.sweep.split() if a.sweep else [a.grid]:
        scene = make_scene(tmp / f"scene_{grid}", grid)
        kx, _, kz = grid.partition("x")
        lights = int(kx) * int(kz or kx)
        for integrator in a.integrators.split(","):
            say(f"\n{lights} lights ({grid}), --integrator {integrator}, 160x120, 4 spp, "
                f"{a.rounds} rounds, reference: tree at {a.ref_spp} spp")
            ref = reference(a.build, scene, integrator, a.ref_spp, a.threads)
            chosen = ["all", "tree"] if a.sweep else a.selections.split(",")
            configs = [(s if s != "auto" else "auto (default)", a.build, scene, ["--light-selection", s])
                       for s in chosen]
            if a.old and not a.sweep:
                configs.insert(0, ("old build's default", a.old, scene, []))
            table(say, compare(configs, integrator, ref, a.rounds, a.threads, tmp), "all")


def granularity(a, say, tmp):
    """The quads at one radiance as lights of their own against one mesh light of them."""
    own = make_scene(tmp / "uniform", a.grid, "--uniform")
    merged = make_scene(tmp / "merged", a.grid, "--merged")
    for integrator in a.integrators.split(","):
        say(f"\nthe {a.grid} grid's quads at one radiance, --integrator {integrator}, 160x120, 4 spp, "
            f"{a.rounds} rounds, reference: tree at {a.ref_spp} spp on the lights of their own")
        ref = reference(a.build, own, integrator, a.ref_spp, a.threads)
        configs = [("quads as lights, tree", a.build, own, ["--light-selection", "tree"]),
                   ("one mesh light, all", a.build, merged, ["--light-selection", "all"])]
        table(say, compare(configs, integrator, ref, a.rounds, a.threads, tmp), configs[0][0])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=str(ROOT / "build"), help="the build to measure (bin/ and lib/)")
    ap.add_argument("--old", default="", help="another build whose default selection is also measured")
    ap.add_argument("--grid", default="32")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--integrators", default="path,whitted")
    ap.add_argument("--selections", default="all,power,tree,auto")
    ap.add_argument("--ref-spp", type=int, default=1024)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--sweep", default="", help="grids (e.g. '1x1 2x1 4x2') to compare all and tree on")
    ap.add_argument("--granularity", action="store_true", help="the quads as lights of their own or as one mesh light")
    ap.add_argument("--out", default="", help="also write the output to this file")
    a = ap.parse_args()
    lines = []

    def say(s=""):
        print(s, flush=True)
        lines.append(s)

    tree = subprocess.run(["git", "-C", str(ROOT), "describe", "--always", "--dirty"], capture_output=True,
                          text=True).stdout.strip()
    say(f"bench_many_lights: tree {tree}, {platform.node()}, {cpu_model()}, {os.cpu_count()} cores, "
        f"load {os.getloadavg()[0]:.1f}")
    say("command: " + " ".join([Path(sys.argv[0]).name] + sys.argv[1:]))
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        if a.granularity:
            granularity(a, say, tmp)
        else:
            selections(a, say, tmp)
    if a.out:
        Path(a.out).write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()

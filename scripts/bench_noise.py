#!/usr/bin/env python3
"""Noise benchmark of the direct-light estimators (issue 15).

For each scene: a reference with the same camera rays (same seed and spp) and
converged direct light (mis, many light samples), then the
estimator before issue 15 (`before`: a build of --before-commit, light
samples uniform by area from a multi-jittered set per shading point) and the
three estimators of penumbra-estimators (mis and light, the choices of
penumbra's --direct-light, and area, the baseline no public API offers) at
the same camera and light samples
(equal samples), then `before` with its light samples raised until its render
time matches that of `mis` (equal time). The figure is the relative MSE
against the reference, mean over pixels and channels of
(x - ref)^2 / (ref^2 + 0.01): only the direct-light estimator's noise, not
the pixel filter's. Times are render_seconds of --stats-json, the smaller of
two interleaved runs, so start-up and image writing do not count. Last, the
textbook scene's ns per camera sample with `area` and `mis`, 1 thread.

Writes the raw output (docs/bench_noise.txt), all figures (docs/bench_noise.json)
and the section of docs/benchmarks.md (scripts/benchmarks_doc_noise.md; run
scripts/make_benchmarks_doc.py afterwards). Scenes under ../shared are skipped
when it is absent.

  scripts/bench_noise.py [--penumbra build/bin/penumbra] [--estimators build/bin/penumbra-estimators]
                         [--before-commit 44fc004 | --before BIN]
                         [--spp 4] [--light-samples 4] [--ref-light-samples 256] [--threads 2]
                         [--textbook-spp 25]

--before-commit is checked out with `git worktree` under build-before/ and its
`penumbra` built there (once; later runs reuse it).
"""
import argparse
import json
import os
import platform
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared"

SCENES = [
    ("glossy floor, sphere light", ROOT / "assets/scenes/bench/glossy_sphere_light.json", []),
    ("glossy floor, rectangle light", ROOT / "assets/scenes/bench/glossy_rectangle_light.json", []),
    # Its illum 7 sphere (glass today, rendered as its mirror part before issue 16) is made
    # illum 3, a mirror, in a copy (mirror_copy), so that both renderers render the same scene.
    ("CornellBox-Sphere", SHARED / "scenes/cornell_mcguire/CornellBox-Sphere.obj", ["--width", "256", "--height", "256"]),
    ("lecture_area_light", ROOT / "assets/scenes/lecture_area_light.json", ["--width", "300", "--height", "200"]),
]


def mirror_copy(obj, tmp):
    """A copy of an OBJ and its MTL in tmp with every `illum 7` (glass) made `illum 3` (mirror)."""
    dst = tmp / "mirror_copy"
    dst.mkdir(exist_ok=True)
    (dst / obj.name).write_bytes(obj.read_bytes())
    for mtl in obj.parent.glob(obj.stem + ".mtl"):
        (dst / mtl.name).write_text(mtl.read_text().replace("illum 7", "illum 3"))
    return dst / obj.name


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        n = w * h * channels
        data = struct.unpack(("<" if scale < 0 else ">") + "f" * n, f.read(4 * n))
    return data


def rel_mse(img, ref):
    return sum((x - r) ** 2 / (r * r + 0.01) for x, r in zip(img, ref)) / len(ref)


def render(exe, scene, extra, out, stats, spp, light_samples, mode, threads, seed=1):
    """Renders with exe: the `before` build's penumbra (mode None) or penumbra-estimators with that estimator."""
    cmd = [str(exe), str(scene), "-o", str(out), "--stats-json", str(stats), "--spp", str(spp),
           "--light-samples", str(light_samples), "--seed", str(seed), "--threads", str(threads)] + extra
    cmd += ["--estimator", mode] if mode else ["-q"]
    p = subprocess.run(cmd, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit(f"bench_noise: {' '.join(cmd)} failed:\n{p.stderr}")
    return json.loads(Path(stats).read_text())


def build_before(commit):
    """penumbra of `commit`, built once under build-before/<commit>."""
    base = ROOT / "build-before" / commit
    exe = base / "build/bin/penumbra"
    if exe.exists():
        return exe
    if not (base / "src").exists():
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(base / "src"), commit], check=True)
    subprocess.run(["cmake", "-S", str(base / "src"), "-B", str(base / "build"), "-DBUILD_TESTING=OFF"], check=True,
                   stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(base / "build"), "-j", str(os.cpu_count()), "--target", "penumbra-cli"],
                   check=True, stdout=subprocess.DEVNULL)
    return exe


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--penumbra", default=str(ROOT / "build/bin/penumbra"), help="for the textbook timing")
    ap.add_argument("--estimators", default=str(ROOT / "build/bin/penumbra-estimators"))
    ap.add_argument("--before-commit", default="44fc004",
                    help="the commit before issue 15, whose estimator is the baseline")
    ap.add_argument("--before", default="", help="its penumbra binary, if already built")
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--light-samples", type=int, default=4)
    ap.add_argument("--ref-light-samples", type=int, default=256)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--textbook-spp", type=int, default=25, help="camera samples for the textbook timing (0: skip)")
    ap.add_argument("--only", default="", help="run only the scenes whose name contains this")
    ap.add_argument("--out-dir", default=str(ROOT / "docs"))
    ap.add_argument("--doc-part", default=str(ROOT / "scripts/benchmarks_doc_noise.md"))
    a = ap.parse_args()
    before = Path(a.before) if a.before else build_before(a.before_commit)

    lines = []

    def say(s=""):
        print(s, flush=True)
        lines.append(s)

    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    say(f"bench_noise: commit {commit}, {platform.node()}, {cpu}, {os.cpu_count()} cores")
    say(f"settings: --spp {a.spp} --light-samples {a.light_samples} --threads {a.threads}; "
        f"reference: mis, --spp {a.spp} --light-samples {a.ref_light_samples} (same seed: same camera rays)")
    say(f"before: {before} (commit {a.before_commit})")
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for name, scene, extra in SCENES:
            if a.only not in name:
                continue
            if not scene.exists():
                say(f"\n{name}: skipped ({scene} is absent)")
                continue
            say(f"\n{name} ({scene.name}{' ' + ' '.join(extra) if extra else ''})")
            if scene.suffix == ".obj":
                scene = mirror_copy(scene, tmp)
                say("  illum 7 made illum 3 (a mirror) in a copy: the same scene for both renderers")

            def run(ls, mode, tag):
                exe = before if mode == "before" else a.estimators
                st = render(exe, scene, extra, tmp / f"{tag}.pfm", tmp / f"{tag}.json", a.spp, ls,
                            None if mode == "before" else mode, a.threads)
                return st["render_seconds"], st["rays"]["total"], read_pfm(tmp / f"{tag}.pfm")

            # Each renderer against its own converged image, so that any other
            # difference between the renderers' images does not count as noise.
            t_ref, _, ref_now = run(a.ref_light_samples, "mis", "ref")
            t_ref_before, _, ref_before = run(a.ref_light_samples, "before", "ref_before")
            say(f"  references: {t_ref:.2f} s (mis), {t_ref_before:.2f} s (before)")
            r = {"scene": name, "reference_seconds": t_ref, "modes": {}}
            # Equal samples, each twice (interleaved) for the time; before also at
            # twice the light samples, for its time per light sample.
            ls, ls2 = a.light_samples, 2 * a.light_samples
            runs = [("before", ls), ("area", ls), ("light", ls), ("mis", ls), ("before", ls2)]
            times, errs, rays = {}, {}, {}
            for rep in range(2):
                for mode, n in runs:
                    t, nrays, img = run(n, mode, f"{mode}{n}_{rep}")
                    times.setdefault((mode, n), []).append(t)
                    if rep == 0:
                        errs[(mode, n)] = rel_mse(img, ref_before if mode == "before" else ref_now)
                        rays[(mode, n)] = nrays
            t = {k: min(v) for k, v in times.items()}
            base = errs[("before", ls)]
            say(f"  {'estimator':<10} {'light spp':>9} {'time s':>8} {'rays':>10} {'relMSE':>11} {'vs before':>9}")
            for mode, n in runs:
                e = errs[(mode, n)]
                say(f"  {mode:<10} {n:>9} {t[(mode, n)]:>8.3f} {rays[(mode, n)]:>10} {e:>11.4e} {e / base:>9.3f}")
                r["modes"][f"{mode}_{n}"] = {"light_samples": n, "seconds": t[(mode, n)], "rays": rays[(mode, n)],
                                             "rel_mse": e}
            # Equal time: before's light samples raised until its time matches mis's
            # (time linear in the light samples, from the two runs of before).
            # Refined by up to three secant steps on measured times (the machine is shared:
            # a single small timing can be far off).
            t_mis, t_ls = t[("mis", ls)], t[("before", ls)]
            slope = max((t[("before", ls2)] - t_ls) / (ls2 - ls), 1e-6)
            n_eq = max(ls, min(64 * ls, round(ls + (t_mis - t_ls) / slope)))
            for step in range(3):
                t1, nrays, img = run(n_eq, "before", "before_eq")
                t2, _, _ = run(n_eq, "before", "before_eq2")
                t_eq, e_eq = min(t1, t2), rel_mse(img, ref_before)
                if abs(t_eq / t_mis - 1) < 0.1 or n_eq == ls and t_eq > t_mis or step == 2:
                    break
                if t_eq > t_ls and n_eq > ls:
                    slope = (t_eq - t_ls) / (n_eq - ls)
                n_next = max(ls, min(64 * ls, round(ls + (t_mis - t_ls) / slope)))
                if n_next == n_eq:
                    break
                n_eq = n_next
            say(f"  {'before =t':<10} {n_eq:>9} {t_eq:>8.3f} {nrays:>10} {e_eq:>11.4e} {e_eq / base:>9.3f}")
            e_mis = errs[("mis", ls)]
            r["before_equal_time"] = {"light_samples": n_eq, "seconds": t_eq, "rel_mse": e_eq}
            r["mis_over_before_equal_samples"] = e_mis / base
            r["mis_over_before_equal_time"] = e_mis / e_eq
            r["time_mis_over_before"] = t[("mis", ls)] / t[("before", ls)]
            say(f"  mis / before: {e_mis / base:.3f} at equal samples, {e_mis / e_eq:.3f} at equal time "
                f"(before with {n_eq} light samples, {t_eq:.3f} s against mis {t[('mis', ls)]:.3f} s)")
            results.append(r)
        textbook = None
        tb = SHARED / "bench/textbook_fig18_04.json"
        if a.textbook_spp > 0 and tb.exists():
            say(f"\ntextbook_fig18_04.json, --threads 1 --spp {a.textbook_spp} (scene's 1 light sample): "
                "ns per camera sample (render_seconds / camera rays), runs interleaved")
            ns = {"before": [], "mis": []}
            for rep in range(3):
                for mode in ("before", "mis"):
                    exe = before if mode == "before" else a.penumbra
                    cmd = [str(exe), str(tb), "-o", str(tmp / "tb.pfm"), "-q", "--threads", "1", "--spp",
                           str(a.textbook_spp), "--stats-json", str(tmp / "tb.json")]
                    if mode == "mis":
                        cmd += ["--direct-light", "mis"]
                    subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
                    st = json.loads((tmp / "tb.json").read_text())
                    ns[mode].append(st["render_seconds"] / st["rays"]["camera"] * 1e9)
            for mode in ("before", "mis"):
                say(f"  {mode:<6} " + " ".join(f"{x:7.1f}" for x in ns[mode]) + f"   median {sorted(ns[mode])[1]:.1f}")
            textbook = {m: sorted(v)[1] for m, v in ns.items()}
    out = Path(a.out_dir)
    (out / "bench_noise.txt").write_text("\n".join(lines) + "\n")
    (out / "bench_noise.json").write_text(json.dumps({"commit": commit, "cpu": cpu, "spp": a.spp,
                                                      "light_samples": a.light_samples,
                                                      "ref_light_samples": a.ref_light_samples,
                                                      "threads": a.threads, "before_commit": a.before_commit,
                                                      "scenes": results,
                                                      "textbook_ns_per_camera_sample": textbook}, indent=1) + "\n")
    write_doc_part(Path(a.doc_part), a, commit, cpu, results, textbook, lines)


def write_doc_part(path, a, commit, cpu, results, textbook, lines):
    o = ["## Direct-light noise: MIS against the estimator before issue 15 (a separate run)\n\n",
         "This section is not part of the run above: it is `scripts/bench_noise.py` (issue 15), run on its own at\n",
         f"commit {commit} on {cpu} with `--threads {a.threads}`, and generated from that run.\n",
         "The figure is the relative MSE, mean over pixels and channels of (x − ref)² / (ref² + 0.01), against a\n",
         f"reference with the same camera rays (same seed and `--spp {a.spp}`) and converged direct light\n",
         f"(`--light-samples {a.ref_light_samples}`, rendered by the same renderer: each is measured against its own\n",
         "converged image), so only the direct-light estimator's noise is measured, not the pixel filter's.\n",
         "CornellBox-Sphere is rendered from a copy whose `illum 7` sphere (glass since issue 16, the mirror part\n",
         f"of it before) is `illum 3`, a mirror, so that both renderers render the same scene. `before` is the renderer of commit {a.before_commit}, before issue 15\n",
         "(light samples uniform in area, a multi-jittered set per shading point, a hash per sample for one-sample\n",
         "lights); the script builds it. `area`, `light` and `mis` are today's estimators (`penumbra-estimators`;\n",
         "`light` and `mis` are `--direct-light`'s, `area` the baseline no public API offers), which all draw\n",
         "from the pixel's Owen-scrambled (0,2)-sequence (stratified per shading point and across the pixel's camera\n",
         "samples): area-uniform light samples, solid-angle light samples, and light + Phong BRDF samples with the\n",
         f"power heuristic (the default). Equal samples: `--spp {a.spp} --light-samples {a.light_samples}` for all; equal\n",
         "time: `before` with its light samples raised until its render time matches that of `mis`. Times are\n",
         "`render_seconds`, the smaller of two interleaved runs. Target: `mis` ≤ 0.5× `before` at equal samples,\n",
         "no worse at equal time.\n\n",
         "| scene | relMSE before | relMSE mis | mis / before, equal samples | mis / before, equal time | render time mis / before |\n",
         "|---|---:|---:|---:|---:|---:|\n"]
    for r in results:
        m = r["modes"]
        ls = a.light_samples
        o.append(f"| {r['scene']} | {m[f'before_{ls}']['rel_mse']:.3e} | {m[f'mis_{ls}']['rel_mse']:.3e} | "
                 f"{r['mis_over_before_equal_samples']:.3f} | {r['mis_over_before_equal_time']:.3f} "
                 f"(before: {r['before_equal_time']['light_samples']} light samples) | {r['time_mis_over_before']:.2f} |\n")
    if textbook:
        o.append(f"\nThe textbook scene (`../shared/bench/textbook_fig18_04.json`, diffuse only, one 4×4 rectangle light,\n"
                 f"1 light sample, `--threads 1 --spp {a.textbook_spp}`): {textbook['before']:.0f} ns per camera sample\n"
                 f"before and {textbook['mis']:.0f} ns with `mis` (median of three interleaved runs each).\n")
    built = f"--before {a.before} " if a.before else ""
    o.append("\nCommand: `scripts/bench_noise.py " + f"--before-commit {a.before_commit} {built}--spp {a.spp} "
             f"--light-samples {a.light_samples} --ref-light-samples {a.ref_light_samples} --threads {a.threads} "
             f"--textbook-spp {a.textbook_spp}` (raw output `docs/bench_noise.txt`, figures `docs/bench_noise.json`):\n\n```\n"
             + "\n".join(lines) + "\n```\n")
    path.write_text("".join(o))


if __name__ == "__main__":
    sys.exit(main())

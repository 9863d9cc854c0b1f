#!/usr/bin/env python3
"""Penumbra's path tracer against Blender 3.4's Cycles: time, noise and efficiency on a suite of scenes.

    scripts/bench_cycles.py [--scenes a,b,...] [--rounds N] [--threads N] [--penumbra BUILD_DIR]
                            [--cache DIR] [--json OUT] [--ref-factor K] [--scale F] [--spp-scale F]

Installs Debian's `blender` when missing (as root). Each scene is rendered by Penumbra
(`--integrator path --light-samples 1 --max-depth D`, its defaults otherwise) and by Cycles (CPU,
`blender -b`, scripts/blender_render.py), alternating (Penumbra first in odd rounds, Cycles first
in even ones), with the same geometry, camera, image size, samples per pixel, environment and
path length (Cycles' max bounces B = D - 1, every bounce kind), both on --threads threads.

Same scene: both read one Lambert copy of the scene's OBJ (scripts/blender_common.py:
`lambert_copy`, cached under --cache): Kd, Ke and map_Kd only, mirror and glass made diffuse with
their reflectance as albedo, duplicate faces dropped, textures copied beside it. Cycles gets a Diffuse
BSDF (roughness 0) times the sRGB texture, and emission from the front side only, as Penumbra emits.
Cycles: box pixel filter one pixel wide (Penumbra's), no denoising, no adaptive sampling, no
clamping, no path guiding, no light tree where the version has one; its other defaults stay (the
light threshold, the world importance map at 1024). Both write linear float images.

Timed span, the same for both: scene preparation on the renderer's side (BVH build, texture and
environment image decoding, light and environment sampling structures) plus all samples; not the
process start, the scene file's parsing or import, nor the image writing. Penumbra: build_seconds +
render_seconds of --stats-json. Cycles: the wall time of bpy.ops.render.render() (Blender's export
of the scene to Cycles, then Cycles' device update and sampling); its own progress lines split that
into preparation and sampling, printed beside it. The time is the median over the rounds.

Noise: relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01) (as
scripts/bench_noise.py), against a converged reference per renderer (the same renderer and
settings with K times the samples and another seed, cached under --cache, keyed by scene and
settings; a Penumbra reference made by another build is reused with a note, delete it to remake).
K is at least 64 for many_lights: Cycles' rare bright samples there left its 16x reference's mean
1.2% below Penumbra's, while the two renderers' 64x references agree within 0.1%.
Each round has its own seed; the figure is the mean over the rounds, times K / (K + 1), which
removes the reference's own variance (the same per-sample variance at K times the samples).
Efficiency = 1 / (relMSE x time); the table gives Penumbra's over Cycles'.

Correctness, independent of load: the two references' means must agree within 1% per channel
(whole image, and named regions such as the Cornell box walls); a scene lit by an environment map
is first checked for the map's orientation: the map alone, seen straight by both renderers
in three directions, must agree far better than with either image mirrored.

--scale and --spp-scale shrink the image and the samples for trying the tool; their figures are not
the suite's.
"""
import argparse
import dataclasses
import datetime
import hashlib
import json
import os
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import blender_common as bc  # noqa: E402
import make_many_lights  # noqa: E402

TOOL = "bench_cycles.py"
MEANS_TOLERANCE = 0.01
REFERENCE_SEED = 1000003


@dataclasses.dataclass
class SuiteScene:
    name: str
    title: str
    source: object  # an OBJ path, or a function writing the OBJ into a folder and returning its path
    width: int
    height: int
    spp: int
    camera: dict
    environment: dict = None
    regions: dict = dataclasses.field(default_factory=dict)  # name: (x0, y0, x1, y1), fractions, y down
    # The least reference factor for this scene: where one renderer's samples carry rare, large values
    # (Cycles' under many small lights), a reference of 16x the samples has a mean that is off by more
    # than the 1% the means are checked to.
    min_ref_factor: int = 1


CORNELL_CAMERA = {"eye": [0, 1, 3.9], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov": 40}
CORNELL_REGIONS = {  # with CORNELL_CAMERA: patches of one surface each, clear of the light and the boxes
    "left wall": (0.08, 0.25, 0.16, 0.75), "right wall": (0.84, 0.25, 0.92, 0.75),
    "back wall": (0.40, 0.20, 0.60, 0.38), "ceiling": (0.20, 0.05, 0.38, 0.12), "floor": (0.20, 0.90, 0.45, 0.97),
}


def many_lights(folder):
    """make_many_lights.py --obj's scene (the one scripts/bench_many_lights.py measures), its OBJ."""
    source = Path(folder) / "many_lights_source"
    make_many_lights.obj_scene(source, 32, 32)
    return source / "many_lights.obj"


SCENES = [
    SuiteScene("cornell", "McGuire CornellBox-Original", bc.SHARED / "scenes/cornell_mcguire/CornellBox-Original.obj",
               256, 256, 64, CORNELL_CAMERA, regions=CORNELL_REGIONS),
    SuiteScene("dragon", "dragon_100k/dragon.obj under a constant environment 1,1,1",
               bc.SHARED / "scenes/dragon_100k/dragon.obj", 256, 192, 64,
               {"eye": [12, 8, 18], "look_at": [0, 4.5, 0], "up": [0, 1, 0], "fov": 40}, {"rgb": [1, 1, 1]}),
    SuiteScene("many_lights", "floor and boxes under 1,024 small emitters (make_many_lights.py --obj)",
               many_lights, 160, 120, 16, {"eye": [0, 5.5, 22], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 28},
               min_ref_factor=64),
    SuiteScene("cornell_sphere", "McGuire CornellBox-Sphere, mirror and glass made Lambert",
               bc.SHARED / "scenes/cornell_mcguire/CornellBox-Sphere.obj", 256, 256, 64, CORNELL_CAMERA,
               regions={"left wall": (0.08, 0.30, 0.16, 0.60), "right wall": (0.84, 0.30, 0.92, 0.60),
                        "back wall": (0.40, 0.35, 0.60, 0.55), "floor": (0.40, 0.92, 0.60, 0.97)}),
    SuiteScene("sponza", "Sponza (Dabrovic), textured, under hdri_polyhaven/adams_place_bridge_1k.hdr",
               bc.SHARED / "scenes/sponza_dabrovic/sponza.obj", 256, 192, 64,
               {"eye": [-8, 3, 0], "look_at": [8, 6, 0], "up": [0, 1, 0], "fov": 75},
               {"file": str(bc.SHARED / "scenes/hdri_polyhaven/adams_place_bridge_1k.hdr"), "rotate": 0.0}),
]


def say(*args):
    print(*args, flush=True)


def digest(obj):
    return hashlib.sha256(json.dumps(obj, sort_keys=True, default=str).encode()).hexdigest()[:16]


def file_digest(*paths):
    h = hashlib.sha256()
    for p in paths:
        h.update(Path(p).read_bytes())
    return h.hexdigest()[:16]


class Bench:
    def __init__(self, args):
        self.args = args
        self.build = Path(args.penumbra)
        self.cache = Path(args.cache)
        self.max_depth = args.max_depth
        self.fingerprint = bc.build_fingerprint(self.build)
        self.blender = bc.blender_version()
        self.blender_script = file_digest(bc.BLENDER_SCRIPT)

    # -- scenes ------------------------------------------------------------------------------

    def prepare(self, scene):
        """The Lambert copy both renderers read, made once per source and cached."""
        folder = self.cache / "scenes" / scene.name
        source = scene.source(folder) if callable(scene.source) else Path(scene.source)
        if not source.exists():
            return None
        stamp = folder / "prepared.json"
        key = {"source": str(source), "digest": file_digest(source), "script": file_digest(Path(bc.__file__))}
        if stamp.exists():
            saved = json.loads(stamp.read_text())
            if saved["key"] == key:
                return saved
        copy, table, dropped = bc.lambert_copy(source, folder / "lambert")
        saved = {"key": key, "obj": str(copy), "materials": table, "duplicate_faces_dropped": dropped,
                 "digest": file_digest(copy, copy.with_name(copy.stem + ".lambert.mtl"))}
        stamp.write_text(json.dumps(saved, indent=1))
        return saved

    def settings(self, scene):
        a = self.args
        return {"width": max(8, round(scene.width * a.scale)), "height": max(8, round(scene.height * a.scale)),
                "spp": max(1, round(scene.spp * a.spp_scale))}

    # -- renders -----------------------------------------------------------------------------

    def penumbra(self, scene, prepared, size, spp, seed, threads, out, workdir):
        options = ["--integrator", "path", "--max-depth", str(self.max_depth), "--light-samples", "1",
                   "--spp", str(spp), "--width", str(size["width"]), "--height", str(size["height"]),
                   "--seed", str(seed), "--threads", str(threads)]
        options += bc.camera_options(scene.camera) + bc.environment_options(scene.environment)
        stats = bc.run_penumbra(TOOL, self.build, prepared["obj"], options, out, Path(workdir) / "stats.json")
        return {"seconds": bc.penumbra_seconds(stats), "prepare_seconds": stats["build_seconds"],
                "sampling_seconds": stats["render_seconds"]}

    def cycles(self, scene, prepared, size, spp, seed, threads, out, workdir):
        job = {"scene": prepared["obj"], "materials": prepared["materials"], "camera": scene.camera,
               "environment": scene.environment, "width": size["width"], "height": size["height"], "spp": spp,
               "max_bounces": self.max_depth - 1, "seed": seed, "threads": threads, "output": str(out)}
        report = bc.run_cycles(TOOL, job, workdir)
        return {"seconds": report["render_seconds"], "prepare_seconds": report["prepare_seconds"],
                "sampling_seconds": report["sampling_seconds"]}

    def reference(self, scene, prepared, renderer, size, spp, workdir):
        """The converged image of one renderer, cached."""
        key = {"scene": scene.name, "obj": prepared["digest"], "size": size, "spp": spp, "camera": scene.camera,
               "environment": scene.environment, "max_depth": self.max_depth, "renderer": renderer,
               "seed": REFERENCE_SEED}
        if renderer == "cycles":
            key.update(blender=self.blender, script=self.blender_script)
        name = f"{scene.name}-{renderer}-{digest(key)}"
        image, meta = self.cache / "references" / f"{name}.pfm", self.cache / "references" / f"{name}.json"
        if image.exists() and meta.exists():
            saved = json.loads(meta.read_text())
            if renderer == "penumbra" and saved.get("build") != self.fingerprint:
                say(f"  note: the Penumbra reference was made by another build ({saved.get('build')}); "
                    f"delete {image} to remake it")
            return bc.read_pfm(image), saved
        image.parent.mkdir(parents=True, exist_ok=True)
        say(f"  rendering the {renderer} reference ({spp} spp), cached as {image.name}")
        render = self.penumbra if renderer == "penumbra" else self.cycles
        run = render(scene, prepared, size, spp, REFERENCE_SEED, 0, image, workdir)
        saved = {"key": key, "seconds": run["seconds"], "build": self.fingerprint if renderer == "penumbra" else None,
                 "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")}
        meta.write_text(json.dumps(saved, indent=1, default=str))
        return bc.read_pfm(image), saved

    # -- checks ------------------------------------------------------------------------------

    def environment_check(self, scene, workdir):
        """The map alone, seen straight in three directions by both renderers: relMSE between them,
        and with Cycles' image mirrored (which a flipped mapping would make the smaller)."""
        env = scene.environment
        key = digest({"env": env, "blender": self.blender, "script": self.blender_script, "build": self.fingerprint})
        saved = self.cache / "environment_checks" / f"{Path(env['file']).stem}-{key}.json"
        if saved.exists():
            return json.loads(saved.read_text())
        probe_dir = self.cache / "scenes" / "environment_probe"
        probe_dir.mkdir(parents=True, exist_ok=True)
        probe = probe_dir / "probe.obj"  # one tiny triangle far below: the camera sees only the map
        probe.write_text("v 0 -1000 0\nv 0.001 -1000 0\nv 0 -1000 0.001\nf 1 2 3\n")
        copy, table, _ = bc.lambert_copy(probe, probe_dir / "lambert")
        prepared = {"obj": str(copy), "materials": table}
        views = {"-z": ([0, 0, -1], [0, 1, 0]), "+x": ([1, 0, 0], [0, 1, 0]), "+y (up)": ([0, 1, 0], [0, 0, -1])}
        size, spp, result = {"width": 96, "height": 96}, 16, {}
        for view, (look, up) in views.items():
            probe_scene = dataclasses.replace(scene, camera={"eye": [0, 0, 0], "look_at": look, "up": up, "fov": 90})
            self.penumbra(probe_scene, prepared, size, spp, 1, 0, workdir / "env_p.pfm", workdir)
            self.cycles(probe_scene, prepared, size, spp, 1, 0, workdir / "env_c.pfm", workdir)
            p, c = bc.read_pfm(workdir / "env_p.pfm"), bc.read_pfm(workdir / "env_c.pfm")
            result[view] = {"rel_mse": bc.rel_mse(c, p), "rel_mse_mirrored": bc.rel_mse(bc.mirrored(c), p)}
        result = {"views": result, "agree": all(v["rel_mse"] < 0.01 and v["rel_mse"] * 10 < v["rel_mse_mirrored"]
                                                for v in result.values())}
        saved.parent.mkdir(parents=True, exist_ok=True)
        saved.write_text(json.dumps(result, indent=1))
        return result

    # -- one scene ---------------------------------------------------------------------------

    def run_scene(self, scene, workdir):
        prepared = self.prepare(scene)
        if prepared is None:
            say(f"\n{scene.name}: skipped ({scene.source} is absent)")
            return None
        size = self.settings(scene)
        spp = size.pop("spp")
        say(f"\n{scene.name}: {scene.title}, {size['width']}x{size['height']}, {spp} spp, "
            f"--max-depth {self.max_depth} / Cycles max bounces {self.max_depth - 1}")
        if prepared["duplicate_faces_dropped"]:
            say(f"  {prepared['duplicate_faces_dropped']} duplicate face(s) dropped from the copy")
        result = {"scene": scene.name, "title": scene.title, **size, "spp": spp, "camera": scene.camera,
                  "environment": scene.environment}
        if scene.environment and "file" in scene.environment:
            check = self.environment_check(scene, workdir)
            result["environment_check"] = check
            say("  environment orientation: " + ("agree" if check["agree"] else "DISAGREE") + "; relMSE Cycles "
                "against Penumbra (mirrored): " + ", ".join(f"{v} {r['rel_mse']:.2e} ({r['rel_mse_mirrored']:.2e})"
                                                            for v, r in check["views"].items()))
        ref_factor = max(self.args.ref_factor, scene.min_ref_factor)
        ref_spp = spp * ref_factor
        refs = {r: self.reference(scene, prepared, r, size, ref_spp, workdir) for r in ("penumbra", "cycles")}
        result["references"] = {r: {"spp": ref_spp, "seconds": meta["seconds"], "date": meta["date"]}
                                for r, (_, meta) in refs.items()}
        runs = {"penumbra": [], "cycles": []}
        for rnd in range(self.args.rounds):
            order = ["penumbra", "cycles"] if rnd % 2 == 0 else ["cycles", "penumbra"]
            for renderer in order:
                out = workdir / f"{renderer}.pfm"
                render = self.penumbra if renderer == "penumbra" else self.cycles
                run = render(scene, prepared, size, spp, rnd + 1, self.args.threads, out, workdir)
                run["rel_mse"] = bc.rel_mse(bc.read_pfm(out), refs[renderer][0])
                runs[renderer].append(run)
            say(f"  round {rnd + 1} ({order[0]} first): " + ", ".join(
                f"{r} {runs[r][-1]['seconds']:.3f} s relMSE {runs[r][-1]['rel_mse']:.3e}" for r in ("penumbra", "cycles")))
        correction = ref_factor / (ref_factor + 1)
        for renderer, rs in runs.items():
            med = lambda k: statistics.median(r[k] for r in rs) if all(r[k] is not None for r in rs) else None
            summary = {"seconds": med("seconds"), "prepare_seconds": med("prepare_seconds"),
                       "sampling_seconds": med("sampling_seconds"),
                       "rel_mse": statistics.fmean(r["rel_mse"] for r in rs) * correction, "rounds": rs}
            summary["efficiency"] = 1.0 / (summary["rel_mse"] * summary["seconds"])
            result[renderer] = summary
        result["efficiency_ratio"] = result["penumbra"]["efficiency"] / result["cycles"]["efficiency"]
        result["means"] = self.compare_means(scene, refs["penumbra"][0], refs["cycles"][0])
        return result

    def compare_means(self, scene, pen, cyc):
        regions = {"whole image": None, **scene.regions}
        out = {}
        for region, box in regions.items():
            p, c = pen.channel_means(box), cyc.channel_means(box)
            diff = [(a / b - 1.0) if b > 0 else float("inf") for a, b in zip(p, c)]
            out[region] = {"penumbra": p, "cycles": c, "relative_difference": diff,
                           "agree": all(abs(d) <= MEANS_TOLERANCE for d in diff)}
            say(f"  converged means, {region}: Penumbra/Cycles - 1 = "
                + ", ".join(f"{ch} {d * 100:+.2f}%" for ch, d in zip("RGB", diff))
                + ("" if out[region]["agree"] else f"  DISAGREE (over {MEANS_TOLERANCE:.0%})"))
        return out


def print_table(results):
    say("\n| scene | Penumbra | Cycles | efficiency Penumbra / Cycles |")
    say("| --- | --- | --- | --- |")
    for r in results:
        p, c = r["penumbra"], r["cycles"]

        def cell(s):
            split = ""
            if s["prepare_seconds"] is not None:
                split = f" ({s['prepare_seconds']:.2f} + {s['sampling_seconds']:.2f})"
            return f"{s['seconds']:.2f} s{split}, relMSE {s['rel_mse']:.3g}"

        say(f"| {r['scene']}, {r['width']}x{r['height']}, {r['spp']} spp | {cell(p)} | {cell(c)} | "
            f"{r['efficiency_ratio']:.2f} |")
    say("Times: median wall seconds of the timed span (preparation + sampling); relMSE: mean over the rounds.")
    bad = [f"{r['scene']} ({region})" for r in results for region, m in r["means"].items() if not m["agree"]]
    say("Converged means agree within 1% per channel everywhere." if not bad else
        "Converged means differ by more than 1% in: " + ", ".join(bad))


def main():
    sys.stdout.reconfigure(line_buffering=True)
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    names = [s.name for s in SCENES]
    ap.add_argument("--scenes", default=",".join(names), help="comma-separated, of: " + ", ".join(names))
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--threads", type=int, default=2, help="threads of each renderer (references use all cores)")
    ap.add_argument("--penumbra", default=str(bc.ROOT / "build"), help="build folder with bin/penumbra and lib/")
    ap.add_argument("--cache", default=os.path.join(os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")),
                                                     "penumbra", "bench_cycles"))
    ap.add_argument("--json", help="write every figure here")
    ap.add_argument("--max-depth", type=int, default=10, help="Penumbra's path length (Cycles: one bounce less)")
    ap.add_argument("--ref-factor", type=int, default=16, help="reference samples = K x the scene's samples (many_lights: at least 64 x)")
    ap.add_argument("--scale", type=float, default=1.0, help="image size factor (trying the tool only)")
    ap.add_argument("--spp-scale", type=float, default=1.0, help="samples factor (trying the tool only)")
    args = ap.parse_args()
    wanted = [n.strip() for n in args.scenes.split(",") if n.strip()]
    unknown = [n for n in wanted if n not in names]
    if unknown:
        ap.error(f"unknown scene(s) {', '.join(unknown)}; the suite has {', '.join(names)}")
    if bc.penumbra_exe(args.penumbra) is None:
        bc.fail(TOOL, f"{args.penumbra}/bin/penumbra: no penumbra executable (--penumbra BUILD_DIR)")
    if args.rounds < 1 or args.threads < 0 or args.ref_factor < 1 or args.max_depth < 1:
        ap.error("--rounds, --ref-factor and --max-depth must be at least 1, --threads at least 0")
    bc.ensure_blender(TOOL)
    bench = Bench(args)
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "unknown")
    header = {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
              "machine": f"{cpu}, {os.cpu_count()} hardware threads, load {os.getloadavg()[0]:.2f}",
              "penumbra": f"{args.penumbra} (build {bench.fingerprint})", "blender": bench.blender,
              "command": " ".join([f"scripts/{TOOL}", *sys.argv[1:]])}
    for k, v in header.items():
        say(f"{k}: {v}")
    results = []
    with bc.temp_dir("bench_cycles.") as tmp:
        for scene in SCENES:
            if scene.name in wanted:
                r = bench.run_scene(scene, Path(tmp))
                if r:
                    results.append(r)
    if results:
        print_table(results)
    if args.json:
        Path(args.json).write_text(json.dumps({**header, "scenes": results}, indent=1, default=str) + "\n")
        say(f"wrote {args.json}")


if __name__ == "__main__":
    main()

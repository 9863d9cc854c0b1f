#!/usr/bin/env python3
"""Memory of instancing: 20 dragons copied against 20 instances of one dragon.

Writes two JSON scenes of 20 placements of the 100k-triangle Stanford dragon
(../shared/scenes/dragon_100k/dragon.obj): one with 20 `mesh` entries (20
copies), one with a prototype and 20 `instance` entries, the same transforms.
Renders each with `build/bin/penumbra --stats-json`, alternating copied and
instanced runs (the machine drifts), and writes scripts/benchmarks_doc_instancing.md
(the section of docs/benchmarks.md; regenerate that page with
scripts/make_benchmarks_doc.py) with the commands, the machine, the raw output
and the figures computed from it. Run from the repository root after a build.

With --edit it times instead, through the Python module of build/python, what
moving one dragon of the instanced scene costs: Renderer.prepare of the scene
against Renderer.update(prepared, transforms={0: ...}) (medians of --rounds),
and prints both and their ratio (the goal: an update within 5% of a prepare).
"""
import argparse
import json
import math
import os
import platform
import shutil
import statistics
import struct
import subprocess
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DRAGON = ROOT.parent / "shared" / "scenes" / "dragon_100k" / "dragon.obj"


def placements(n):
    """n transforms on a 5-wide grid, each dragon turned differently."""
    out = []
    for i in range(n):
        x, z = (i % 5 - 2) * 16.0, (i // 5) * -12.0
        out.append({"rotate": [i * 37.0 % 360.0, 0, 1, 0], "translate": [x, 0, z]})
    return out


def scene(instanced, n):
    doc = {
        "camera": {"eye": [0, 45, 60], "look_at": [0, 0, -18], "fov": 50},
        "materials": {"jade": {"kd": [0.2, 0.6, 0.3], "ks": 0.2, "n": 40}, "floor": {"kd": 0.6}},
        "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"}],
        "lights": [{"type": "point", "position": [20, 60, 40], "intensity": 4000},
                   {"type": "directional", "direction": [-0.3, -1, -0.4], "irradiance": 0.4}],
    }
    if instanced:
        doc["prototypes"] = [{"name": "dragon",
                              "shapes": [{"type": "mesh", "file": "dragon.obj", "material": "jade"}]}]
        doc["shapes"] += [{"type": "instance", "prototype": "dragon", "transform": t} for t in placements(n)]
    else:
        doc["shapes"] += [{"type": "mesh", "file": "dragon.obj", "material": "jade", "transform": t}
                          for t in placements(n)]
    return doc


def read_pfm(path):
    data = Path(path).read_bytes()
    header, pos = [], 0
    while len(header) < 3:
        end = data.index(b"\n", pos)
        header.append(data[pos:end].decode())
        pos = end + 1
    w, h = (int(v) for v in header[1].split())
    fmt = ("<" if float(header[2]) < 0 else ">") + "f" * (3 * w * h)
    return struct.unpack(fmt, data[pos:pos + 12 * w * h])


def machine():
    cpu = "unknown CPU"
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    mem = next(l for l in Path("/proc/meminfo").read_text().splitlines() if l.startswith("MemTotal"))
    gib = int(mem.split()[1]) / 2**20
    return f"{cpu}, {os.cpu_count()} cores, {gib:.0f} GiB, {platform.system()} {platform.release()}"


EDIT_TIMING = """
import statistics, sys, time
import penumbra
rounds = int(sys.argv[2])
r = penumbra.Renderer()
scene = r.load_scene(sys.argv[1])
moved = penumbra.Matrix3x4.translate((-29.0, 4.0, 3.0)) @ penumbra.Matrix3x4.rotate(75.0, (0, 1, 0))
prepare, update = [], []
for _ in range(rounds):
    t0 = time.perf_counter()
    prepared = r.prepare(scene)
    t1 = time.perf_counter()
    edited = r.update(prepared, transforms={0: moved})
    t2 = time.perf_counter()
    prepare.append(t1 - t0)
    update.append(t2 - t1)
    del prepared, edited
p, u = statistics.median(prepare), statistics.median(update)
print(f"prepare (median of {rounds}): {p * 1e3:.1f} ms   runs: " + " ".join(f"{t * 1e3:.1f}" for t in prepare))
print(f"update, one dragon moved (median of {rounds}): {u * 1e3:.2f} ms   runs: " + " ".join(f"{t * 1e3:.2f}" for t in update))
print(f"update / prepare: {100 * u / p:.2f}%")
"""


def edit_benchmark(work, rounds):
    """Times prepare against update (one dragon moved) of the instanced scene."""
    built_for = (ROOT / "build" / "python" / "penumbra" / "_built_for.py").read_text()
    python = built_for.split('INTERPRETER = "', 1)[1].split('"', 1)[0]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "build" / "python"))
    p = subprocess.run([python, "-c", EDIT_TIMING, str(work / "instanced.json"), str(rounds)], env=env,
                       capture_output=True, text=True)
    print(p.stdout + p.stderr, end="")
    if p.returncode != 0:
        raise SystemExit(p.returncode)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--dragons", type=int, default=20)
    ap.add_argument("--out", default=str(ROOT / "scripts" / "benchmarks_doc_instancing.md"))
    ap.add_argument("--edit", action="store_true", help="time moving one dragon against preparing the scene")
    a = ap.parse_args()
    if not DRAGON.exists():
        raise SystemExit(f"{DRAGON} is missing: this benchmark needs ../shared")
    if a.edit:
        work = Path(tempfile.mkdtemp(prefix="penumbra-edit-"))
        shutil.copy(DRAGON, work / "dragon.obj")
        (work / "instanced.json").write_text(json.dumps(scene(True, a.dragons), indent=1))
        try:
            edit_benchmark(work, a.rounds)
        finally:
            shutil.rmtree(work)
        return
    cli = ROOT / "build" / "bin" / "penumbra"
    work = Path(tempfile.mkdtemp(prefix="penumbra-inst-"))
    shutil.copy(DRAGON, work / "dragon.obj")
    for kind in ("copied", "instanced"):
        (work / f"{kind}.json").write_text(json.dumps(scene(kind == "instanced", a.dragons), indent=1))
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    load_before = os.getloadavg()[0]
    log, stats = [], {"copied": [], "instanced": []}
    for r in range(a.rounds):
        for kind in ("copied", "instanced"):
            cmd = ["/usr/bin/time", "-f", "wall %e s, user %U s, sys %S s, max RSS %M KB", str(cli),
                   str(work / f"{kind}.json"), "-q", "--width", "320", "--height", "240", "--spp", "1",
                   "--accel", "embree", "-o", str(work / f"{kind}.pfm"), "--stats-json", str(work / "st.json")]
            p = subprocess.run(cmd, capture_output=True, text=True)
            shown = " ".join(c if c != str(cli) else "build/bin/penumbra" for c in cmd).replace(str(work), "$DIR")
            log.append(f"$ {shown}\n{p.stdout}{p.stderr}".rstrip())
            if p.returncode != 0:
                raise SystemExit("\n".join(log))
            st = json.loads((work / "st.json").read_text())
            keep = {k: st[k] for k in ("triangles", "peak_memory_mib", "build_seconds", "render_seconds",
                                       "total_seconds")}
            log.append(json.dumps(keep))
            stats[kind].append(keep)
    ca, ia = read_pfm(work / "copied.pfm"), read_pfm(work / "instanced.pfm")
    diffs = [abs(x - y) for x, y in zip(ca, ia)]
    pixels = len(ca) // 3
    differing = sum(1 for p in range(pixels)
                    if max(diffs[3 * p:3 * p + 3]) > 1e-3 * max(1.0, max(abs(v) for v in ca[3 * p:3 * p + 3])))
    image_line = (f"last copied and instanced renders compared: {differing} of {pixels} pixels differ by more than 1e-3 (relative), "
                  f"largest difference {max(diffs):.3g}, mean {sum(diffs) / len(diffs):.3g}")
    log.append(image_line)
    shutil.rmtree(work)

    def med(kind, key):
        return statistics.median(s[key] for s in stats[kind])

    rows = []
    for kind in ("copied", "instanced"):
        load = statistics.median(s["total_seconds"] - s["build_seconds"] - s["render_seconds"] for s in stats[kind])
        rows.append(f"| {kind} | {stats[kind][0]['triangles']:,} | {med(kind, 'peak_memory_mib'):.0f} MiB | "
                    f"{load:.2f} s | {med(kind, 'build_seconds'):.2f} s | {med(kind, 'render_seconds'):.2f} s |")
    ratio = med("copied", "peak_memory_mib") / med("instanced", "peak_memory_mib")
    text = f"""## Instancing memory: 20 dragons (a separate run)

This section is not part of the run above: `python3 scripts/bench_instancing.py` wrote it (commit {commit},
{a.rounds} rounds, copied and instanced runs alternating) and the figures below are computed from the raw
output beside them. Machine: {machine()}; load average {load_before:.1f} when it started (other
builds share the machine: wall times exceed CPU times, memory is unaffected).

The scenes are 20 placements (rotations about y, a 5 x 4 grid) of the Stanford dragon
(`../shared/scenes/dragon_100k/dragon.obj`, 100,000 triangles): **copied** has 20 `mesh` entries, each
loading and transforming the OBJ file; **instanced** has one prototype and 20 `instance` entries
([scene format](scene-format.md#prototypes-and-instances)), which become one Embree scene of the dragon
and 20 Embree instances of it ([accelerators](accelerators.md#instances)). Both render 320x240 at 1 spp
with Embree; peak memory is the process's peak resident set (`peak_memory_mib` of `--stats-json`),
load = total - build - render; medians of the {a.rounds} runs.

| scene | triangles rendered | peak memory | load | Embree build | render |
| --- | --- | --- | --- | --- | --- |
{rows[0]}
{rows[1]}

Peak memory, copied / instanced: {ratio:.1f}x. Images: the {image_line} (instances are intersected in
object space, so t, u and v round differently from the copies'; see
[accelerators](accelerators.md#instances)).

```
{chr(10).join(log)}
```
"""
    Path(a.out).write_text(text)
    print(text)


if __name__ == "__main__":
    main()

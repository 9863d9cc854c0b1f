#!/usr/bin/env python3
"""Generates docs/benchmarks.md from one benchmark run (scripts/run_benchmarks.sh).

Inputs (all written by that run): docs/bench_rays.json and .txt (penumbra-bench
--json and its stdout), docs/bench_anchors.json and .txt (scripts/bench_anchors.sh).
Every figure on the page is computed here from those files, so the summary
cannot disagree with the results beside it.
"""
import argparse
import json
import statistics
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def fmt(x, digits=2):
    return "-" if x is None else f"{x:.{digits}f}"


def median(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def met(value, target, smaller_is_better):
    if value is None:
        return "not measured"
    ok = value <= target if smaller_is_better else value >= target
    return "yes" if ok else "**no**"


def span(values, digits=2):
    values = [v for v in values if v is not None]
    if not values:
        return "-"
    lo, hi = min(values), max(values)
    return fmt(lo, digits) if abs(hi - lo) < 10 ** -digits else f"{fmt(lo, digits)} – {fmt(hi, digits)}"


def anchor_figures(anchors):
    runs = anchors["runs"]
    fig = {}
    help_walls = [r["wall"] for r in runs if r["name"] == "help"]
    fig["help_wall"] = median(help_walls)
    fig["help_rss_mib"] = median([r["max_rss_kib"] / 1024 for r in runs if r["name"] == "help"])
    fig["cornell_rss_mib"] = median([r["max_rss_kib"] / 1024 for r in runs if r["name"] == "cornell32"])
    # ns per camera sample per thread, from the render time of --stats-json.
    fig["textbook"] = {}
    for scene in ("textbook_fig18_04", "textbook_fig24_06"):
        per = {}
        for t in (1, 2):
            ns, cpu_ns, walls, render = [], [], [], []
            for r in runs:
                if r["name"] == scene and r["kind"] == f"penumbra_{t}t" and r["stats"]:
                    st = r["stats"]
                    ns.append(st["render_seconds"] * t / st["rays"]["camera"] * 1e9)
                    # CPU time of the whole process (start-up and image writing
                    # included) per camera sample: what load from other
                    # processes on the machine inflates least.
                    cpu_ns.append((r["user"] + r["sys"]) / st["rays"]["camera"] * 1e9)
                    render.append(st["render_seconds"])
                    walls.append(r["wall"])
            per[t] = {"ns": median(ns), "cpu_ns": median(cpu_ns), "render": median(render), "wall": median(walls),
                      "runs": len(ns)}
        speedup = None
        if per[1]["render"] and per[2]["render"]:
            speedup = per[1]["render"] / per[2]["render"]
        fig["textbook"][scene] = {"per": per, "speedup": speedup}
    # POV-Ray pairs: runs alternate povray, penumbra within a config.
    fig["pov"] = {}
    for c in anchors["config"]:
        pov = [r for r in runs if r["name"] == c["name"] and r["kind"] == "povray"]
        pen = [r for r in runs if r["name"] == c["name"] and r["kind"] == "penumbra"]
        n = min(len(pov), len(pen))
        if n == 0:
            continue
        wall = [pov[i]["wall"] / pen[i]["wall"] for i in range(n)]
        cpu = [(pov[i]["user"] + pov[i]["sys"]) / (pen[i]["user"] + pen[i]["sys"]) for i in range(n)]
        fig["pov"][c["name"]] = {
            "config": c, "pairs": n, "wall_ratio": median(wall), "cpu_ratio": median(cpu),
            "pov_wall": median([p["wall"] for p in pov]), "pen_wall": median([p["wall"] for p in pen]),
            "pov_cpu": median([p["user"] + p["sys"] for p in pov]),
            "pen_cpu": median([p["user"] + p["sys"] for p in pen]),
        }
    return fig


def threads_section(log):
    """The thread-scaling table from a saved run of scripts/bench_threads.sh, and its raw output."""
    runs = {}
    for line in log.splitlines():
        f = line.split()
        if line.startswith("#") or len(f) != 5 or f[0] == "scene":
            continue
        runs.setdefault((f[0], int(f[1])), []).append((float(f[3]), f[4] == "yes"))
    out = [(ROOT / "scripts" / "benchmarks_doc_threads.md").read_text().rstrip() + "\n\n"]
    out.append("| scene | threads | render s (median) | speed-up over 1 thread | over 2 threads, per pair of threads "
               "| every image identical to 1 thread |\n| --- | ---: | ---: | ---: | ---: | --- |\n")
    for (scene, t), rs in runs.items():
        sec = median([r[0] for r in rs])
        one = median([r[0] for r in runs.get((scene, 1), [])]) if (scene, 1) in runs else None
        two = median([r[0] for r in runs.get((scene, 2), [])]) if (scene, 2) in runs else None
        over_one = fmt(one / sec) if one else "-"
        over_two = fmt(two / sec / (t / 2)) if two and t >= 2 else "-"
        out.append(f"| {scene} | {t} | {fmt(sec, 3)} | {over_one} | {over_two} | "
                   f"{'yes' if all(r[1] for r in rs) else '**no**'} |\n")
    out.append("\nRaw output (`docs/bench_threads.txt`):\n\n```\n" + log.rstrip() + "\n```\n")
    return "".join(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--docs", default=str(ROOT / "docs"))
    ap.add_argument("--out", default=str(ROOT / "docs" / "benchmarks.md"))
    a = ap.parse_args()
    docs = Path(a.docs)
    bench = json.loads((docs / "bench_rays.json").read_text())
    bench_log = (docs / "bench_rays.txt").read_text()
    anchors = json.loads((docs / "bench_anchors.json").read_text())
    anchors_log = (docs / "bench_anchors.txt").read_text()
    intro = (ROOT / "scripts" / "benchmarks_doc_intro.md").read_text()
    fig = anchor_figures(anchors)
    scenes = bench["scenes"]
    targets = bench["targets"]

    frame_q = {s["name"]: s["ratios"]["frame_over_query_nt"] for s in scenes}
    scaling = {s["name"]: s["ratios"]["render_scaling_nt_over_1t"] for s in scenes}
    fq_worst = max((v for v in frame_q.values() if v is not None), default=None)
    sc_worst = min((v for v in scaling.values() if v is not None), default=None)
    tb = fig["textbook"]["textbook_fig18_04"]
    ns_tb = tb["per"][1]["ns"]
    pov = fig["pov"]

    out = [intro.rstrip() + "\n"]
    out.append("\n## Results\n\n")
    out.append(
        f"One run of `scripts/run_benchmarks.sh`: penumbra-bench on {bench['date']} "
        f"(`{bench['command']}`, {bench['total_seconds']:.0f} s), the anchors on {anchors['date']} at commit "
        f"{anchors['commit']} (`{anchors['command']}`).\n\n"
        f"**Machine.** {bench['machine']['cpu']}, {bench['machine']['hardware_threads']} hardware threads "
        f"(load average at the anchors' start: {anchors['machine']['load_average_at_start']}; "
        "penumbra-bench's own two threads run just before). These machines drift 10-40% in absolute speed "
        "from minute to minute: the interleaved ratios are the figures to compare, the absolute times "
        "are this run's.\n")

    out.append("\n### Issue 14's targets\n\n")
    out.append("| measure | result | target | met? |\n| --- | ---: | ---: | --- |\n")
    out.append(f"| ns per camera sample per thread, `textbook_fig18_04.json`, 1 thread (median of "
               f"{tb['per'][1]['runs']}; render wall time / whole-process CPU time) | {fmt(ns_tb, 0)} / "
               f"{fmt(tb['per'][1]['cpu_ns'], 0)} | ≤ 60 | {met(ns_tb, 60, True)} |\n")
    for name, label in (("noaa_n8", "POV-Ray / Penumbra, `room`, no AA, 8x8 vs `--light-samples 64`, 2 threads"),
                        ("aa3_n4", "POV-Ray / Penumbra, `room`, AA 3x3 + 4x4 vs `--spp 16 --light-samples 16`")):
        p = pov.get(name)
        if p:
            out.append(f"| {label} (median of {p['pairs']} pairs; wall / CPU) | {fmt(p['wall_ratio'])} / "
                       f"{fmt(p['cpu_ratio'])} | ≥ 4 | {met(p['wall_ratio'], 4, False)} |\n")
        else:
            out.append(f"| {label} | povray not installed | ≥ 4 | not measured |\n")
    worst_fq_scene = max((k for k, v in frame_q.items() if v is not None), key=lambda k: frame_q[k], default="-")
    out.append(f"| frame / pure query time (penumbra-bench), every scene | {span(frame_q.values())} "
               f"(worst: {worst_fq_scene}) | ≤ {targets['frame_over_query_max']} | "
               f"{met(fq_worst, targets['frame_over_query_max'], True)} |\n")
    worst_sc_scene = min((k for k, v in scaling.items() if v is not None), key=lambda k: scaling[k], default="-")
    out.append(f"| 2-thread / 1-thread frame speed-up (penumbra-bench), every scene | {span(scaling.values())} "
               f"(worst: {worst_sc_scene}) | ≥ {targets['render_scaling_min']} | "
               f"{met(sc_worst, targets['render_scaling_min'], False)} |\n")
    out.append(f"| 2-thread / 1-thread render time, `textbook_fig18_04.json` (whole image) | {fmt(tb['speedup'])} | "
               f"≥ 1.9 | {met(tb['speedup'], 1.9, False)} |\n")
    out.append(f"| `penumbra --help` wall time (median of 10); peak memory of a 32-triangle render to PFM | "
               f"{fmt(fig['help_wall'], 3)} s; {fmt(fig['cornell_rss_mib'], 0)} MiB | ≤ 0.03 s; ≤ 40 MiB | "
               f"{met(fig['help_wall'], 0.03, True)}; {met(fig['cornell_rss_mib'], 40, True)} (a PFM loads no image "
               "library; writing any other format loads OpenImageIO, about 125 MiB more: "
               "`scripts/bench_startup.sh` measures both) |\n")

    out.append("\n### Anchor scenes\n\n")
    out.append("| scene | threads | ns per camera sample per thread (render wall) | ns per camera sample "
               "(process CPU) | render s | whole process wall s |\n| --- | ---: | ---: | ---: | ---: | ---: |\n")
    for scene, f in fig["textbook"].items():
        for t in (1, 2):
            p = f["per"][t]
            out.append(f"| `{scene}.json` | {t} | {fmt(p['ns'], 0)} | {fmt(p['cpu_ns'], 0)} | {fmt(p['render'])} | "
                       f"{fmt(p['wall'])} |\n")
    if pov:
        out.append(f"\nPOV-Ray ({anchors['povray']}) against Penumbra on `room.pov` / `room.json` (512×512) and on "
                   "Figure 24.6 (`assets/scenes/bench/textbook_fig24_06.pov` / `textbook_fig24_06.json`, 600×400), "
                   "2 threads each, whole processes, interleaved pairs (medians):\n\n")
        out.append("| scene | POV-Ray switches | Penumbra options | POV wall s | Penumbra wall s | ratio (wall) | "
                   "POV CPU s | Penumbra CPU s | ratio (CPU) |\n"
                   "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n")
        for p in pov.values():
            c = p["config"]
            out.append(f"| {c.get('scene', 'room')} | `{c['povray']}` | `{c['penumbra']}` | {fmt(p['pov_wall'])} | "
                       f"{fmt(p['pen_wall'])} | "
                       f"{fmt(p['wall_ratio'])} | {fmt(p['pov_cpu'])} | {fmt(p['pen_cpu'])} | {fmt(p['cpu_ratio'])} |\n")

    out.append("\n### penumbra-bench ratios per scene\n\n")
    out.append("| scene | triangles | primitives | frame/q | renderNT | cam/raw 1T | cam/raw 2T | build | memory |\n"
               "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n")
    for s in scenes:
        r = s["ratios"]
        out.append(f"| {s['name']} | {s['triangles']} | {s['primitives']} | {fmt(r['frame_over_query_nt'])} | "
                   f"{fmt(r['render_scaling_nt_over_1t'])} | {fmt(r['camera_renderer_over_raw_1t'])} | "
                   f"{fmt(r['camera_renderer_over_raw_nt'])} | {fmt(r['build_renderer_over_raw'])} | "
                   f"{fmt(r['memory_renderer_over_raw'])} |\n")
    ag = bench["agreement"]
    out.append(f"\nAgreement: naive vs Embree {ag['naive_vs_embree']['mismatches']} of "
               f"{ag['naive_vs_embree']['compared']} rays differ, raw vs Embree {ag['raw_vs_embree']['mismatches']} "
               f"of {ag['raw_vs_embree']['compared']} (limit {ag['max_fraction'] * 100:.2f} %): "
               f"{'passed' if ag['passed'] else '**failed**'}.\n")
    if (docs / "bench_rays.png").exists():
        out.append("\n![Rays per second against triangle count, two threads](bench_rays.png)\n")

    out.append("\n### Raw output of penumbra-bench (`docs/bench_rays.txt`; all figures in `docs/bench_rays.json`)\n\n")
    out.append("```\n" + bench_log.rstrip() + "\n```\n")
    out.append("\n### Raw output of the anchors (`docs/bench_anchors.txt`; all runs in `docs/bench_anchors.json`)\n\n")
    out.append("```\n" + anchors_log.rstrip() + "\n```\n")
    threads_log = docs / "bench_threads.txt"
    if threads_log.exists():
        out.append(threads_section(threads_log.read_text()))
    # Sections measured by separate runs, each with its own commands and output.
    for part in ("benchmarks_doc_scale.md", "benchmarks_doc_loading.md", "benchmarks_doc_instancing.md",
                 "benchmarks_doc_noise.md"):
        path = ROOT / "scripts" / part
        if path.exists():
            out.append("\n" + path.read_text())
    Path(a.out).write_text("".join(out))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Times two builds of penumbra against each other on one scene: the A/B behind
the ratios of docs/benchmarks.md's intro and docs/accelerators.md.

    scripts/ab_builds.py A_DIR B_DIR [--rounds N] [--format EXT] [--label-a TEXT] [--label-b TEXT] -- SCENE [OPTIONS...]

A_DIR and B_DIR each hold a build's bin/ and lib/ (a build folder, or a copy of
one). Every round copies both afresh (on this machine the same library bytes ran
at different speeds from different files, docs/benchmarks.md) and runs them one
after the other, the order alternating between rounds, each with its own
lib/ on LD_LIBRARY_PATH and `-q -o` a PFM (or `--format png|exr|...`: the whole
process then includes encoding that format). It prints the machine, the command,
every round's wall and CPU (user + sys) times, the median of each build's times and of
the ratios B/A, and whether the two builds' images were the same: the same bytes for
PFM, the same pixels (`idiff`) for other formats, whose encoders may differ.
Exits non-zero when a render fails.
"""
import argparse
import shlex
import datetime
import filecmp
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def same_image(a, b):
    """PFM: the same bytes; other formats: the same pixels (their encoders' metadata may differ)."""
    if a.endswith(".pfm"):
        return filecmp.cmp(a, b, shallow=False)
    return subprocess.run(["idiff", "-q", "-fail", "0", "-warn", "0", a, b], stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL).returncode == 0


def main():
    sys.stdout.reconfigure(line_buffering=True)
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("a")
    parser.add_argument("b")
    parser.add_argument("--rounds", type=int, default=6)
    parser.add_argument("--format", default="pfm", help="extension of the image written (default pfm)")
    parser.add_argument("--label-a", default=None)
    parser.add_argument("--label-b", default=None)
    argv = sys.argv[1:]
    if "--" not in argv:
        parser.error("give the scene and penumbra's options after --")
    split = argv.index("--")
    args = parser.parse_args(argv[:split])
    render = argv[split + 1:]
    if not render:
        parser.error("give the scene and penumbra's options after --")
    builds = {"A": args.a, "B": args.b}
    for name, folder in builds.items():
        exe = os.path.join(folder, "bin", "penumbra")
        if not os.access(exe, os.X_OK):
            sys.exit(f"ab_builds.py: {exe}: no penumbra executable (build {name})")
        if not os.path.isdir(os.path.join(folder, "lib")):
            sys.exit(f"ab_builds.py: {folder}/lib: no library folder (build {name})")
    labels = {"A": args.label_a or args.a, "B": args.label_b or args.b}

    print(f"date: {datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}")
    print(f"machine: {cpu_model()}, {os.cpu_count()} hardware threads, load {os.getloadavg()[0]:.2f}")
    print(f"command: {shlex.join(['scripts/ab_builds.py', *sys.argv[1:]])}")
    print(f"A: {labels['A']}\nB: {labels['B']}")
    times = {"A": [], "B": []}
    cpu = {"A": [], "B": []}
    same = True
    with tempfile.TemporaryDirectory(prefix="ab_builds.") as tmp:
        for r in range(args.rounds):
            order = ["A", "B"] if r % 2 == 0 else ["B", "A"]
            for name in order:
                copy = os.path.join(tmp, "build_" + name)
                shutil.rmtree(copy, ignore_errors=True)
                os.makedirs(os.path.join(copy, "bin"))
                shutil.copy2(os.path.join(builds[name], "bin", "penumbra"), os.path.join(copy, "bin"))
                shutil.copytree(os.path.join(builds[name], "lib"), os.path.join(copy, "lib"), symlinks=True)
                env = dict(os.environ, LD_LIBRARY_PATH=os.path.join(copy, "lib"))
                out = os.path.join(tmp, f"image_{name}.{args.format}")
                before = os.times()
                start = time.perf_counter()
                done = subprocess.run([os.path.join(copy, "bin", "penumbra"), *render, "-q", "-o", out], env=env)
                seconds = time.perf_counter() - start
                after = os.times()
                cpu[name].append(after.children_user - before.children_user + after.children_system - before.children_system)
                if done.returncode != 0:
                    sys.exit(f"ab_builds.py: build {name} failed (exit {done.returncode}) in round {r + 1}")
                times[name].append(seconds)
            identical = same_image(os.path.join(tmp, f"image_A.{args.format}"), os.path.join(tmp, f"image_B.{args.format}"))
            same = same and identical
            print(f"round {r + 1} ({order[0]} first): A {times['A'][-1]:.3f} s, B {times['B'][-1]:.3f} s, "
                  f"B/A {times['B'][-1] / times['A'][-1]:.3f}; CPU A {cpu['A'][-1]:.3f} s, B {cpu['B'][-1]:.3f} s, "
                  f"B/A {cpu['B'][-1] / cpu['A'][-1]:.3f}; images {'identical' if identical else 'DIFFER'}")
    ratios = [b / a for a, b in zip(times["A"], times["B"])]
    cpu_ratios = [b / a for a, b in zip(cpu["A"], cpu["B"])]
    print(f"median: A {statistics.median(times['A']):.3f} s, B {statistics.median(times['B']):.3f} s; "
          f"B/A median {statistics.median(ratios):.3f} (min {min(ratios):.3f}, max {max(ratios):.3f}); "
          f"images {'identical in every round' if same else 'DIFFER'}")
    print(f"median CPU: A {statistics.median(cpu['A']):.3f} s, B {statistics.median(cpu['B']):.3f} s; "
          f"B/A median {statistics.median(cpu_ratios):.3f} (min {min(cpu_ratios):.3f}, max {max(cpu_ratios):.3f})")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""What watching a render costs: `penumbra SCENE -o X.pfm OPTIONS` against the same with
--preview --preview-exit, alone and with a page watching (a client polling /status every
200 ms and fetching each new image, as the page does), run in turn for ROUNDS rounds.
Prints each round's wall and CPU seconds (the command's user + system time: less
sensitive than wall time to other work on the machine) and the medians, and checks
that all three write the same image bytes.

usage: scripts/bench_preview.py [--build build] [--rounds 3] -- SCENE [penumbra options]"""

import argparse
import json
import os
import pathlib
import platform
import resource
import shlex
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests" / "preview"))
from preview_harness import URL_LINE  # noqa: E402


def cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def watch(port, process, fetched):
    """The page's polling: the status every 200 ms, the image when a newer one is there."""
    seen = 0
    while process.poll() is None:
        try:
            status = json.loads(urllib.request.urlopen(f"http://127.0.0.1:{port}/status", timeout=5).read())
            if status.get("version", 0) > seen:
                urllib.request.urlopen(f"http://127.0.0.1:{port}/image", timeout=5).read()
                seen = status["version"]
                fetched.append(seen)
        except OSError:
            pass
        time.sleep(0.2)


def run(command, page):
    """(wall seconds, CPU seconds, images fetched) of one run."""
    cpu, wall = cpu_seconds(), time.monotonic()
    process = subprocess.Popen(command, stderr=subprocess.PIPE, text=True)
    fetched = []
    watcher = None
    if "--preview" in command:
        port = int(URL_LINE.match(process.stderr.readline().rstrip("\n")).group(1))
        if page:
            watcher = threading.Thread(target=watch, args=(port, process, fetched))
            watcher.start()
    process.stderr.read()
    if process.wait() != 0:
        sys.exit(f"bench_preview: {shlex.join(command)} failed")
    if watcher:
        watcher.join()
    return time.monotonic() - wall, cpu_seconds() - cpu, len(fetched)


def main():
    argv = sys.argv[1:]
    if "--" not in argv:
        sys.exit(__doc__)
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default="build")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv[:argv.index("--")])
    scene_and_options = argv[argv.index("--") + 1:]
    cli = str(pathlib.Path(args.build) / "bin" / "penumbra")
    cpu_name = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
                    platform.processor())
    print(f"date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(f"machine: {cpu_name}, {os.cpu_count()} hardware threads, load {os.getloadavg()[0]:.2f}")
    print(f"command: scripts/bench_preview.py {shlex.join(argv)}")
    kinds = [("plain", [], False), ("preview", ["--preview", "--preview-exit"], False),
             ("preview+page", ["--preview", "--preview-exit"], True)]
    results = {name: [] for name, _, _ in kinds}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.rounds):
            images, line = [], []
            for name, extra, page in kinds:
                out = pathlib.Path(tmp) / f"{name}.pfm"
                wall, cpu, fetched = run([cli, *scene_and_options, "-q", "-o", str(out), *extra], page)
                results[name].append((wall, cpu))
                images.append(out.read_bytes())
                line.append(f"{name} {wall:.2f} s wall, {cpu:.2f} s CPU" + (f" ({fetched} images fetched)" if page else ""))
            same = all(i == images[0] for i in images)
            print(f"round {r + 1}: " + "; ".join(line) + ("; images identical" if same else "; IMAGES DIFFER"))
            if not same:
                sys.exit(1)
    base = [cpu for _, cpu in results["plain"]]
    for name in ("preview", "preview+page"):
        ratios = [cpu / b for (_, cpu), b in zip(results[name], base)]
        walls = [wall / b for (wall, _), (b, _) in zip(results[name], results["plain"])]
        print(f"median {name}/plain: CPU {statistics.median(ratios):.3f} (min {min(ratios):.3f}, max {max(ratios):.3f}), "
              f"wall {statistics.median(walls):.3f}")


if __name__ == "__main__":
    main()

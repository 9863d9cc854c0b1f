"""What scripts/bench_cycles.py and scripts/compare_blender.py share: running Penumbra and Blender's
Cycles (through scripts/blender_render.py) on the same scene, camera and settings, the Lambert copy of
an OBJ scene both renderers read, and image arithmetic on the linear PFM files both write.

Standard library only (the `python3` on PATH need not have numpy); Blender brings its own Python.
"""
import hashlib
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib
from array import array
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared"
BLENDER_SCRIPT = ROOT / "scripts" / "blender_render.py"


def fail(tool, message):
    sys.exit(f"{tool}: {message}")


# ---------------------------------------------------------------------------------------------
# The two renderers

def ensure_blender(tool):
    """Blender on PATH, installed from Debian (3.4.1 on Debian 12) when missing and we are root."""
    if shutil.which("blender"):
        return
    if os.geteuid() == 0 and shutil.which("apt-get"):
        print(f"{tool}: installing blender (Debian package)", file=sys.stderr, flush=True)
        done = subprocess.run(["apt-get", "install", "-y", "-q", "blender"], env=dict(os.environ, DEBIAN_FRONTEND="noninteractive"),
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if done.returncode == 0 and shutil.which("blender"):
            return
        fail(tool, f"apt-get install blender failed:\n{done.stderr[-2000:]}")
    fail(tool, "blender is not installed; run as root to install it, or: sudo apt-get install blender")


def blender_env():
    """The environment Blender runs in: its own folder first on PATH, because Debian's Blender takes
    its Python's home from the first python3 on PATH, and a python3 of another installation (pyenv,
    a virtual environment) lacks the modules Blender needs (numpy)."""
    folder = os.path.dirname(os.path.realpath(shutil.which("blender")))
    return dict(os.environ, PATH=folder + os.pathsep + os.environ.get("PATH", ""))


def blender_version():
    out = subprocess.run(["blender", "-b", "--factory-startup", "--version"], capture_output=True, text=True,
                         env=blender_env()).stdout
    match = re.search(r"^Blender (\S+)", out, re.M)
    return match.group(1) if match else "unknown"


def run_cycles(tool, job, workdir):
    """Renders (or, with job["probe"], only places the camera); returns blender_render.py's report."""
    workdir = Path(workdir)
    job = dict(job, report=str(workdir / "cycles_report.json"))
    job_file = workdir / "cycles_job.json"
    job_file.write_text(json.dumps(job, indent=1))
    cmd = ["blender", "-b", "--factory-startup", "-noaudio", "--python-exit-code", "1",
           "--python", str(BLENDER_SCRIPT), "--", str(job_file)]
    done = subprocess.run(cmd, capture_output=True, text=True, env=blender_env())
    if done.returncode != 0 or not Path(job["report"]).exists():
        fail(tool, f"Cycles failed (exit {done.returncode}) on {job['scene']}:\n"
                   f"{(done.stdout + done.stderr)[-3000:]}")
    report = json.loads(Path(job["report"]).read_text())
    report.update(cycles_phases(done.stdout))
    return report


def cycles_phases(log):
    """Cycles' own progress lines ("... | Time:00:07.52 | ... | Sample 0/64") split its render into
    preparation (until the first sample: scene export, BVH, images, lights, the environment's
    importance map) and sampling; None where the log does not say."""
    def seconds(stamp):
        parts = [float(p) for p in stamp.split(":")]
        return sum(p * 60 ** i for i, p in enumerate(reversed(parts)))

    start = end = None
    for match in re.finditer(r"\| Time:([0-9:.]+) \|.*\| (Sample 0/|Finished)", log):
        if match.group(2) == "Finished":
            end = seconds(match.group(1))
        elif start is None:
            start = seconds(match.group(1))
    if start is None or end is None:
        return {"prepare_seconds": None, "sampling_seconds": None}
    return {"prepare_seconds": start, "sampling_seconds": end - start}


def penumbra_exe(build):
    exe = Path(build) / "bin" / "penumbra"
    if not os.access(exe, os.X_OK):
        return None
    return exe


def build_fingerprint(build):
    """A hash of the build's executable and libraries: which Penumbra made an image."""
    h = hashlib.sha256()
    files = [Path(build) / "bin" / "penumbra"] + sorted((Path(build) / "lib").glob("*.so*"))
    for f in files:
        if f.is_file() and not f.is_symlink():
            h.update(f.name.encode())
            h.update(f.read_bytes())
    return h.hexdigest()[:16]


def vec(v):
    return ",".join(repr(float(x)) for x in v)


def camera_options(cam):
    return ["--eye", vec(cam["eye"]), "--look-at", vec(cam["look_at"]), "--up", vec(cam["up"]),
            "--fov", repr(float(cam["fov"]))]


def environment_options(env):
    if env is None:
        return []
    if "rgb" in env:
        return ["--env", vec(env["rgb"])]
    options = ["--env", str(env["file"])]
    if env.get("rotate"):
        options += ["--env-rotate", repr(float(env["rotate"]))]
    return options


def run_penumbra(tool, build, scene, options, out, stats):
    """One Penumbra process; returns its --stats-json."""
    env = dict(os.environ, LD_LIBRARY_PATH=str(Path(build) / "lib"))
    cmd = [str(penumbra_exe(build)), str(scene), *options, "-q", "-o", str(out), "--stats-json", str(stats)]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        fail(tool, f"Penumbra failed (exit {done.returncode}): {' '.join(cmd)}\n{done.stderr[-3000:]}")
    return json.loads(Path(stats).read_text())


def penumbra_seconds(stats):
    """The span timed for Penumbra: BVH build (scene preparation) plus render, from --stats-json."""
    return stats["build_seconds"] + stats["render_seconds"]


# ---------------------------------------------------------------------------------------------
# The Lambert copy of an OBJ scene

def find_case_insensitive(folder, relative):
    """A file named as in an MTL, matched component by component without regard to case when the
    exact name is absent (Sponza's MTL says SP_LUK.JPG for sp_luk.JPG), as Penumbra matches it."""
    path = Path(folder)
    for part in Path(relative.replace("\\", "/")).parts:
        exact = path / part
        if exact.exists():
            path = exact
            continue
        matches = [p for p in path.iterdir()] if path.is_dir() else []
        matches = [p for p in matches if p.name.lower() == part.lower()]
        if not matches:
            return None
        path = matches[0]
    return path.resolve()


def read_mtl(mtl_path):
    """{name: {"kd", "ks", "ke", "illum", "map_kd"}} from an MTL file, as far as the Lambert copy needs."""
    materials, current = {}, None
    for raw in Path(mtl_path).read_text(errors="replace").splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        key, _, rest = line.partition(" ")
        key, rest = key.strip(), rest.strip()
        if key == "newmtl":
            current = materials.setdefault(rest, {})
        elif current is None:
            continue
        elif key in ("Kd", "Ks", "Ke"):
            values = [float(x) for x in re.findall(r"[-+0-9.eE]+", rest)[:3]]
            current[key.lower()] = values * 3 if len(values) == 1 else values
        elif key == "illum":
            current["illum"] = int(float(rest.split()[0]))
        elif key == "map_Kd" and rest:
            current["map_kd"] = rest.split()[-1]
    return materials


def lambert_of(m, folder):
    """The Lambert version of one MTL material: kd (or, for a mirror or glass, illum 3 to 9, its ks:
    the reflectance becomes diffuse), ke, and map_Kd resolved to a file."""
    kd = m.get("kd") or ([0.6] * 3 if "map_kd" in m else [0.0] * 3)  # tinyobjloader's defaults
    if 3 <= m.get("illum", 2) <= 9:
        kd = m.get("ks", kd)
    texture = find_case_insensitive(folder, m["map_kd"]) if m.get("map_kd") else None
    return {"kd": [max(0.0, x) for x in kd], "ke": [max(0.0, x) for x in m.get("ke", [0.0] * 3)],
            "map_kd": str(texture) if texture else None}


def lambert_copy(obj_path, out_dir):
    """Copies an OBJ into out_dir with one new MTL holding the Lambert version of each of its
    materials (and Penumbra's default material, Kd 0.8, for files without any) and without
    duplicate faces; returns the copy's path, {name: {"kd", "ke", "map_kd"}} (the same materials for
    Cycles) and the number of faces dropped. Mirror and glass (illum 3 to 9) become diffuse with
    their reflectance as albedo; Ks, Ns, maps other than map_Kd, d and Tf are dropped."""
    obj_path, out_dir = Path(obj_path), Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    text = obj_path.read_text(errors="replace")
    libraries = re.findall(r"^[ \t]*mtllib[ \t]+(.+?)[ \t\r]*$", text, re.M)
    table, copied = {}, {}
    for lib in libraries:
        mtl = find_case_insensitive(obj_path.parent, lib)
        if mtl is not None:
            for name, m in read_mtl(mtl).items():
                table[name] = lambert_of(m, mtl.parent)
    # Textures are copied beside the copy, so that neither renderer reads outside its folder.
    for m in table.values():
        source = m["map_kd"]
        if source and source not in copied:
            target = out_dir / "textures" / f"{len(copied)}_{Path(source).name}"
            target.parent.mkdir(exist_ok=True)
            shutil.copyfile(source, target)
            copied[source] = target
        if source:
            m["map_kd"] = str(copied[source])
    new_mtl = obj_path.stem + ".lambert.mtl"
    if libraries:
        first = [True]

        def only_ours(_):
            keep, first[0] = first[0], False
            return f"mtllib {new_mtl}" if keep else ""

        text = re.sub(r"^[ \t]*mtllib[ \t]+.*$", only_ours, text, flags=re.M)
    else:
        table["default"] = {"kd": [0.8, 0.8, 0.8], "ke": [0.0] * 3, "map_kd": None}
        text = f"mtllib {new_mtl}\nusemtl default\n" + text
    lines = []
    for name, m in table.items():
        lines += [f"newmtl {name}", "Kd " + " ".join(f"{x:.6g}" for x in m["kd"]), "Ks 0 0 0"]
        if max(m["ke"]) > 0:
            lines.append("Ke " + " ".join(f"{x:.6g}" for x in m["ke"]))
        if m["map_kd"]:
            lines.append(f"map_Kd {Path(m['map_kd']).relative_to(out_dir)}")
        lines += ["illum 2", ""]
    (out_dir / new_mtl).write_text("\n".join(lines))
    text, dropped = without_duplicate_faces(text)
    copy = out_dir / obj_path.name
    copy.write_text(text)
    return copy, table, dropped


def without_duplicate_faces(text):
    """The OBJ text without faces whose corners lie where an earlier face's do (McGuire's boxes
    repeat their front face as a 'bottom face'). Penumbra's offset rule ignores such a twin; Cycles
    does not, and its shadow rays stop on it (dark stripes). Returns the text and the count dropped."""
    positions, seen, out, dropped = [], set(), [], 0
    for line in text.split("\n"):
        head = line.lstrip()[:2]
        if head == "v " or head == "v\t":
            positions.append(line.split()[1:4])
        elif head == "f " or head == "f\t":
            try:
                corners = [int(tok.split("/")[0]) for tok in line.split()[1:]]
                key = frozenset(tuple(positions[i - 1 if i > 0 else len(positions) + i]) for i in corners)
            except (ValueError, IndexError):
                key = None
            if key is not None and key in seen:
                dropped += 1
                continue
            seen.add(key)
        out.append(line)
    return "\n".join(out), dropped


# ---------------------------------------------------------------------------------------------
# Images: linear RGB float PFM, rows bottom to top

class Image:
    def __init__(self, width, height, data):
        self.width, self.height, self.data = width, height, data  # data: array('f'), RGB interleaved

    def channel_means(self, box=None):
        """Mean of each channel, over the whole image or box = (x0, y0, x1, y1) in fractions of the
        width and height, y from the top."""
        x0, y0, x1, y1 = box or (0, 0, 1, 1)
        c0, c1 = int(x0 * self.width), max(int(x0 * self.width) + 1, int(x1 * self.width))
        r0, r1 = int(y0 * self.height), max(int(y0 * self.height) + 1, int(y1 * self.height))
        sums, n = [0.0, 0.0, 0.0], 0
        for row in range(r0, r1):
            base = (self.height - 1 - row) * self.width * 3
            for c in range(3):
                sums[c] += math.fsum(self.data[base + 3 * c0 + c: base + 3 * c1: 3])
            n += c1 - c0
        return [s / n for s in sums]


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        if kind != b"PF":
            raise ValueError(f"{path}: not an RGB PFM file")
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = array("f")
        data.frombytes(f.read(width * height * 12))
    if (scale < 0) != (sys.byteorder == "little"):
        data.byteswap()
    return Image(width, height, data)


def rel_mse(image, ref):
    """Mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01), as scripts/bench_noise.py."""
    if (image.width, image.height) != (ref.width, ref.height):
        raise ValueError("images of different sizes")
    return math.fsum((x - r) * (x - r) / (r * r + 0.01) for x, r in zip(image.data, ref.data)) / len(ref.data)


def mirrored(image):
    """The image flipped left to right."""
    w, out = image.width, array("f")
    for row in range(image.height):
        line = image.data[row * w * 3:(row + 1) * w * 3]
        for x in range(w - 1, -1, -1):
            out.extend(line[3 * x:3 * x + 3])
    return Image(image.width, image.height, out)


def srgb8(image, exposure_stops=0.0):
    """Display values: linear times 2^exposure, the sRGB curve, clamped, 8-bit; rows top to bottom."""
    scale = 2.0 ** exposure_stops

    def encode(x):
        x = min(1.0, max(0.0, x * scale))
        y = 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055
        return int(y * 255 + 0.5)

    out = bytearray()
    w = image.width
    for row in range(image.height - 1, -1, -1):
        out.extend(encode(x) for x in image.data[row * w * 3:(row + 1) * w * 3])
    return out


def write_png(path, width, height, rgb8):
    """An 8-bit RGB PNG (rows top to bottom), written to a temporary file and renamed."""
    def chunk(kind, payload):
        return struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", zlib.crc32(kind + payload))

    raw = b"".join(b"\0" + bytes(rgb8[y * width * 3:(y + 1) * width * 3]) for y in range(height))
    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(png)
    os.replace(tmp, path)


def temp_dir(prefix):
    return tempfile.TemporaryDirectory(prefix=prefix)

"""`penumbra SCENE --preview` as a server: its one address line, loopback only, the
page's own resources and nothing else, bad requests refused while the render goes
on and finishes, camera moves, the port in use, Ctrl-C."""

import json
import os
import pathlib
import socket
import subprocess
import threading
import time

import pytest

from preview_harness import CORNELL, Preview, png_pixels, raw_request, status_code

SMALL = ["--width", "48", "--height", "48"]
LONG = SMALL + ["--spp", "100000"]  # hours of passes: still rendering whenever a test looks


def test_prints_one_address_line_and_listens_on_loopback_only(cli):
    with Preview(CORNELL, *LONG) as p:
        assert p.stderr_lines[0] == f"preview: http://127.0.0.1:{p.port}/"
        # /proc/net/tcp: the listening socket's local address is 127.0.0.1 (0100007F), never 0.0.0.0.
        listening = [line.split() for line in pathlib.Path("/proc/net/tcp").read_text().splitlines()[1:]]
        ours = [f for f in listening if f[1].endswith(f":{p.port:04X}") and f[3] == "0A"]
        assert [f[1] for f in ours] == [f"0100007F:{p.port:04X}"]
        six = pathlib.Path("/proc/net/tcp6").read_text() if os.path.exists("/proc/net/tcp6") else ""
        assert f":{p.port:04X} " not in six
        assert p.interrupt() == 130
    assert sum(line.startswith("preview:") for line in p.stderr_lines) == 1, p.stderr


def test_serves_the_page_its_status_and_its_image(cli):
    with Preview(CORNELL, *LONG) as p:
        code, headers, body = p.request("/")
        assert code == 200 and headers["Content-Type"] == "text/html; charset=utf-8"
        assert b"<title>Penumbra preview</title>" in body
        assert "default-src 'none'" in headers["Content-Security-Policy"]
        assert headers["Cache-Control"] == "no-store"
        status = p.wait_for(lambda s: s["version"] >= 1, what="the first pass")
        assert status["phase"] == "rendering" and status["spp"] == 100000
        assert status["width"] == 48 and status["scene"] == "cornell.obj"
        assert status["options"].startswith("--eye=")
        jpeg, version, view = p.image()
        assert jpeg.startswith(b"\xff\xd8\xff") and version >= 1 and view == status["view"]  # JPEG while rendering
        # The whole frame at one sample per pixel first, then larger passes.
        later = p.wait_for(lambda s: s["image_samples"] > 1, what="a second pass")
        assert later["samples"] >= later["image_samples"] and later["rays_per_second"] > 0
        assert p.interrupt() == 130


# Raw requests, sent as they are: no client normalises the path first.
TRAVERSALS = [b"/../../etc/passwd", b"/etc/passwd", b"/%2e%2e/%2e%2e/etc/passwd", b"/..%2f..%2fetc%2fpasswd",
              b"/image/../../../etc/passwd", b"//etc/passwd", b"/status/../../etc/passwd", b"/index.html",
              b"/page.html", b"/favicon.ico", b"/image.png", b"/image/x", b"/%00", b"/\\..\\..\\etc\\passwd"]


def get(path, host=None, port=0):
    return b"GET " + path + b" HTTP/1.1\r\nHost: " + (host or f"127.0.0.1:{port}".encode()) + b"\r\n\r\n"


def test_refuses_anything_but_the_pages_own_resources(cli):
    with Preview(CORNELL, *LONG) as p:
        p.wait_for(lambda s: s["version"] >= 1)
        for path in TRAVERSALS:
            answer = raw_request(p.port, get(path, port=p.port))
            assert status_code(answer) in (400, 404), (path, answer[:200])
            assert b"root:" not in answer
        # Methods the resources do not take.
        for method, path in [(b"DELETE", b"/"), (b"PUT", b"/camera"), (b"GET", b"/camera"), (b"POST", b"/status")]:
            request = method + b" " + path + f" HTTP/1.1\r\nHost: 127.0.0.1:{p.port}\r\nContent-Length: 0\r\n\r\n".encode()
            assert status_code(raw_request(p.port, request)) == 405, (method, path)
        # Another name for this machine (DNS rebinding): refused.
        for host in [b"evil.example:%d" % p.port, b"127.0.0.1:1", b""]:
            assert status_code(raw_request(p.port, get(b"/status", host=host))) == 403, host
        assert status_code(raw_request(p.port, f"GET /status HTTP/1.1\r\nHost: localhost:{p.port}\r\n\r\n".encode())) == 200
        assert p.interrupt() == 130


def test_refuses_malformed_and_oversized_requests_and_renders_on(cli):
    with Preview(CORNELL, *LONG) as p:
        before = p.wait_for(lambda s: s["version"] >= 1)
        refused = [
            b"\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03" + bytes(range(256)) + b"\r\n\r\n",   # TLS, garbage
            b"GET\r\n\r\n",
            b"GET / HTTP/9.9\r\nHost: x\r\n\r\n",
            b"GET /" + b"a" * 100_000 + b" HTTP/1.1\r\n\r\n",                                   # a long request line
            get(b"/status", port=p.port)[:-2] + b"X-Long: " + b"b" * 100_000 + b"\r\n\r\n",   # a long header
            get(b"/status", port=p.port)[:-2] + b"X-A: a\r\n" * 5000 + b"\r\n",               # many headers
        ]
        for request in refused:
            answer = raw_request(p.port, request)
            assert status_code(answer) in (None, 400, 404, 405, 413, 414, 431, 505), (request[:40], answer[:200])
        # A flood of header lines: refused after a bounded number of bytes, not read forever.
        with socket.create_connection(("127.0.0.1", p.port), timeout=10) as s:
            s.sendall(b"GET /status HTTP/1.1\r\n")
            sent = 0
            with pytest.raises(OSError):
                while sent < 64 << 20:
                    s.sendall(b"X-Flood: " + b"f" * 1000 + b"\r\n")
                    sent += 1011
        assert sent < 16 << 20, "the server went on reading a request head of %d bytes" % sent
        # Camera moves that are not.
        json_type = {"Content-Type": "application/json"}
        bad_moves = [(b"{", json_type, 400), (b'{"orbit": [1]}', json_type, 400), (b'{"orbit": [1e308, 0]}', json_type, 400),
                     (b'{"zoom": 0}', json_type, 400), (b'{"zoom": NaN}', json_type, 400), (b'{"fly": 1}', json_type, 400),
                     (b'{"zoom": 2, "pan": [0, 0]}', json_type, 400), (b'[]', json_type, 400),
                     (b'{"zoom": 2}', {"Content-Type": "text/plain"}, 415), (b"x" * 5000, json_type, 413)]
        for body, headers, expected in bad_moves:
            code, _, text = p.request("/camera", body, headers)
            assert code == expected, (body[:40], code, text)
        chunked = (f"POST /camera HTTP/1.1\r\nHost: 127.0.0.1:{p.port}\r\nContent-Type: application/json\r\n"
                   "Transfer-Encoding: chunked\r\n\r\n5\r\n{\"zo\r\n0\r\n\r\n").encode()
        assert status_code(raw_request(p.port, chunked)) in (400, 411)
        # None of it moved the camera or stopped the render.
        after = p.wait_for(lambda s: s["version"] > before["version"] + 1, what="passes after the bad requests")
        assert after["view"] == before["view"] and after["options"] == before["options"]
        assert p.interrupt() == 130


def test_many_connections_at_once_neither_stop_the_render_nor_the_server(cli, tmp_path):
    out = tmp_path / "out.pfm"
    options = SMALL + ["--spp", "64", "--seed", "3"]
    with Preview(CORNELL, *options, "-o", out) as p:
        # 300 connections opened at once: a third say nothing, a third half a request, a third a whole one.
        sockets = []
        for i in range(300):
            s = socket.socket()
            s.setblocking(False)
            s.connect_ex(("127.0.0.1", p.port))
            sockets.append(s)
        time.sleep(0.5)
        for i, s in enumerate(sockets):
            try:
                if i % 3 == 1:
                    s.send(b"GET /status HTTP/1.1\r\nHost: ")  # and never the rest
                elif i % 3 == 2:
                    s.send(get(b"/status", port=p.port))
            except OSError:
                pass  # not accepted (yet): the queues are full
        answers = []

        def poll():
            answers.append(status_code(raw_request(p.port, get(b"/status", port=p.port), timeout=5)))

        pollers = [threading.Thread(target=poll) for _ in range(32)]
        for t in pollers:
            t.start()
        for t in pollers:
            t.join()
        assert set(answers) <= {200, None}  # an answer, or a wait
        for s in sockets:
            s.close()
        # Once they are gone the server answers again at once, and the render completes.
        started = time.monotonic()
        assert p.request("/status", timeout=10)[0] == 200
        assert time.monotonic() - started < 5
        p.wait_for(lambda s: s["phase"] == "complete", what="the render after the flood")
        deadline = time.monotonic() + 10
        while not out.exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert p.interrupt() == 130
    # The image written is the one a plain render gives.
    subprocess.run([cli, str(CORNELL), "-q", "-o", str(tmp_path / "plain.pfm"), *options], check=True)
    assert out.read_bytes() == (tmp_path / "plain.pfm").read_bytes()


def test_a_move_restarts_the_render_and_the_copied_options_render_the_same_view(cli, tmp_path):
    pytest.importorskip("OpenImageIO")
    options = SMALL + ["--spp", "16", "--seed", "5"]
    with Preview(CORNELL, *options, "-o", tmp_path / "final.png") as p:
        first = p.wait_for(lambda s: s["version"] >= 1)
        code, _, body = p.move(orbit=[30, 10])
        assert code == 200
        moved = json.loads(body)
        assert moved["view"] == first["view"] + 1 and moved["options"] != first["options"]
        assert moved["samples"] < 16 and moved["phase"] == "rendering"
        assert p.move(zoom=0.8)[0] == 200 and p.move(pan=[0.05, -0.05])[0] == 200
        done = p.wait_for(lambda s: s["phase"] == "complete" and s["image_view"] == s["view"], what="the moved view")
        assert done["view"] == first["view"] + 3 and done["samples"] == 16
        png, _, view = p.image()
        assert view == done["view"] and png.startswith(b"\x89PNG\r\n\x1a\n")  # lossless when complete
        # The preview wrote the final image of the view shown.
        deadline = time.monotonic() + 10
        while not (tmp_path / "final.png").exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert p.interrupt() == 130
    subprocess.run([cli, str(CORNELL), "-q", "-o", str(tmp_path / "copied.png"), *options,
                    *done["options"].split()], check=True)
    copied = png_pixels((tmp_path / "copied.png").read_bytes(), tmp_path, "a.png")
    assert (png_pixels(png, tmp_path, "b.png") == copied).all()
    assert (png_pixels((tmp_path / "final.png").read_bytes(), tmp_path, "c.png") == copied).all()


def test_a_port_in_use_is_a_clear_error(cli, tmp_path):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        r = subprocess.run([cli, str(CORNELL), "--preview", "--preview-port", str(port), "-o", str(tmp_path / "x.png")],
                           capture_output=True, text=True, timeout=60)
    assert r.returncode == 1, r.stderr
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"penumbra: error: --preview-port {port}: cannot listen on "
                                                   f"127.0.0.1:{port}: "), r.stderr
    assert "in use" in r.stderr
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("args,message", [
    (["--preview-port", "70000"], "--preview-port"),
    (["--preview-port", "8000"], "needs --preview"),      # without --preview
    (["--preview-exit"], "needs --preview"),
    (["--preview", "--stats-json", "s.json"], "give -o too"),
    ([], "--output is required"),
])
def test_option_mistakes_are_usage_errors(cli, args, message):
    r = subprocess.run([cli, str(CORNELL), *args], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2, r.stderr
    assert message in r.stderr and r.stderr.endswith("(see --help)\n"), r.stderr


def test_ctrl_c_while_rendering_writes_nothing(cli, tmp_path):
    out = tmp_path / "out.png"
    with Preview(CORNELL, *LONG, "-o", out) as p:
        p.wait_for(lambda s: s["version"] >= 1)
        started = time.monotonic()
        assert p.interrupt() == 130
        assert time.monotonic() - started < 5
    assert os.listdir(tmp_path) == []
    assert "interrupted; no image written" in p.stderr


def test_ctrl_c_after_the_render_keeps_the_image_it_wrote(cli, tmp_path):
    out = tmp_path / "out.png"
    with Preview(CORNELL, *SMALL, "--spp", "4", "-o", out) as p:
        p.wait_for(lambda s: s["phase"] == "complete")
        deadline = time.monotonic() + 10
        while "serving its image until Ctrl-C" not in p.stderr and time.monotonic() < deadline:
            time.sleep(0.05)
        assert "serving its image until Ctrl-C" in p.stderr
        written = out.read_bytes()
        p.request("/status")  # still serving
        assert p.interrupt() == 130
    assert out.read_bytes() == written
    assert sorted(os.listdir(tmp_path)) == ["out.png"]
    assert f"{out} holds the last view rendered to the end" in p.stderr
    assert "wrote" in p.stdout


def test_without_output_it_only_serves(cli, tmp_path):
    with Preview(CORNELL, *SMALL, "--spp", "2", "--preview-exit", "-q") as p:
        assert p.wait() == 0
    assert p.stderr_lines == [f"preview: http://127.0.0.1:{p.port}/"]

"""Runs `penumbra SCENE --preview` for the tests (and scripts/preview_screenshot.py):
the command, its address, its HTTP endpoints, headless Chromium, and reading back
PNG images."""

import json
import os
import pathlib
import re
import shutil
import signal
import socket
import subprocess
import threading
import time
import urllib.error
import urllib.request

SOURCE_DIR = pathlib.Path(os.environ.get("PENUMBRA_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CORNELL = SOURCE_DIR / "assets" / "cornell" / "cornell.obj"
URL_LINE = re.compile(r"^preview: http://127\.0\.0\.1:(\d+)/$")


def penumbra_cli():
    """The penumbra command of this build (PENUMBRA_CLI, else build/bin/penumbra), or None."""
    path = os.environ.get("PENUMBRA_CLI")
    if not path:
        candidate = SOURCE_DIR / "build" / "bin" / "penumbra"
        path = str(candidate) if candidate.exists() else shutil.which("penumbra")
    return path


class Preview:
    """`penumbra SCENE --preview ARGS`, started and waited for until it prints its address."""

    def __init__(self, scene=CORNELL, *args, startup_timeout=60):
        self.command = [penumbra_cli(), str(scene), "--preview", *map(str, args)]
        self.process = subprocess.Popen(self.command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.stderr_lines = []
        self.stdout = ""
        self._listening = threading.Event()
        self._readers = [threading.Thread(target=self._read_stderr, daemon=True),
                         threading.Thread(target=self._read_stdout, daemon=True)]
        for reader in self._readers:
            reader.start()
        if not self._listening.wait(startup_timeout) or self.port is None:
            self.process.kill()
            self.wait()
            raise AssertionError(f"no address line from {self.command}: {self.stderr}")

    port = None

    def _read_stderr(self):
        for line in self.process.stderr:
            self.stderr_lines.append(line.rstrip("\n"))
            match = URL_LINE.match(line.rstrip("\n"))
            if match and self.port is None:
                self.port = int(match.group(1))
                self._listening.set()
        self._listening.set()

    def _read_stdout(self):
        self.stdout = self.process.stdout.read()

    @property
    def stderr(self):
        return "\n".join(self.stderr_lines)

    @property
    def url(self):
        return f"http://127.0.0.1:{self.port}/"

    def request(self, path, data=None, headers=None, method=None, timeout=10):
        """(status, headers, body bytes) of one request; HTTP errors are answers too."""
        req = urllib.request.Request(self.url.rstrip("/") + path, data=data, headers=headers or {}, method=method)
        try:
            with urllib.request.urlopen(req, timeout=timeout) as r:
                return r.status, r.headers, r.read()
        except urllib.error.HTTPError as e:
            return e.code, e.headers, e.read()

    def status(self):
        code, _, body = self.request("/status")
        assert code == 200, body
        return json.loads(body)

    def move(self, **move):
        return self.request("/camera", json.dumps(move).encode(), {"Content-Type": "application/json"})

    def wait_for(self, predicate, timeout=60, what="the preview"):
        """Polls /status until predicate(status) holds; returns that status."""
        deadline = time.monotonic() + timeout
        while True:
            status = self.status()
            if predicate(status):
                return status
            if time.monotonic() > deadline:
                raise AssertionError(f"{what}: timed out; last status {status}")
            time.sleep(0.05)

    def image(self):
        """The latest image: (bytes: a JPEG while rendering, a PNG when complete; its version, its view)."""
        code, headers, body = self.request("/image")
        assert code == 200, body
        return body, int(headers["X-Penumbra-Version"]), int(headers["X-Penumbra-View"])

    def interrupt(self):
        self.process.send_signal(signal.SIGINT)
        return self.wait()

    def wait(self, timeout=30):
        code = self.process.wait(timeout)
        for reader in self._readers:
            reader.join(5)
        for pipe in (self.process.stdout, self.process.stderr):
            pipe.close()
        return code

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.process.poll() is None:
            self.process.kill()
        self.wait()


def raw_request(port, data, timeout=5, read_limit=1 << 16):
    """Sends bytes as they are (no client tidies the path) and returns what comes back
    before the server closes the connection, b"" when it says nothing."""
    with socket.create_connection(("127.0.0.1", port), timeout=timeout) as s:
        try:
            s.sendall(data)
        except (BrokenPipeError, ConnectionResetError):
            pass
        answer = b""
        try:
            while len(answer) < read_limit:
                chunk = s.recv(4096)
                if not chunk:
                    break
                answer += chunk
        except (ConnectionResetError, socket.timeout):
            pass
        return answer


def status_code(answer):
    """The status code of a raw HTTP answer, or None."""
    match = re.match(rb"HTTP/1\.[01] (\d{3})", answer)
    return int(match.group(1)) if match else None


def png_pixels(data, tmp_path, name):
    """The pixels of PNG bytes, through OpenImageIO's Python module (numpy array)."""
    import OpenImageIO as oiio  # noqa: N813 (pytest.importorskip in the callers)
    path = tmp_path / name
    path.write_bytes(data)
    image = oiio.ImageInput.open(str(path))
    try:
        return image.read_image(oiio.UINT8)
    finally:
        image.close()


def chromium_paths():
    """(Chromium, chromedriver) when both are installed, else None."""
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver") or ("/usr/bin/chromedriver" if os.path.exists("/usr/bin/chromedriver") else None)
    return (browser, driver) if browser and driver else None


def loopback_service(driver):
    """chromedriver's Selenium service, reached at 127.0.0.1: Selenium says "localhost", which a
    system without /etc/hosts (CI's pristine Debian root) cannot resolve."""
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common import utils

    class LoopbackService(Service):
        @property
        def service_url(self):
            return f"http://127.0.0.1:{self.port}"

        def is_connectable(self):
            return utils.is_connectable(self.port, "127.0.0.1")

    return LoopbackService(executable_path=driver)


def start_chromium(browser, profile_dir, width, height, timeout=60):
    """Headless Chromium with its DevTools port on 127.0.0.1: (process, port). Started here rather
    than by chromedriver, which would reach it as "localhost" (unresolvable without /etc/hosts)."""
    profile_dir.mkdir(parents=True, exist_ok=True)
    # --no-sandbox: the tests may run as root (CI's pristine Debian root); the page is our own.
    flags = ["--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu",
             f"--window-size={width},{height}", f"--user-data-dir={profile_dir}", "--remote-debugging-port=0",
             "--remote-debugging-address=127.0.0.1", "--no-first-run", "--disable-extensions",
             "--disable-background-networking"]
    process = subprocess.Popen([browser, *flags, "about:blank"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    port_file = profile_dir / "DevToolsActivePort"  # Chromium writes its port there once it listens
    deadline = time.monotonic() + timeout
    while not (port_file.exists() and port_file.read_text().strip()):
        if process.poll() is not None or time.monotonic() > deadline:
            process.kill()
            process.wait()
            raise AssertionError(f"{browser} did not open its DevTools port (exit {process.returncode})")
        time.sleep(0.05)
    return process, int(port_file.read_text().split()[0])


def chromium(profile_dir, width=1000, height=900):
    """Headless Chromium driven through Selenium, with a profile of its own; offline (the page needs
    nothing else). quit() ends the browser too."""
    from selenium import webdriver
    browser, driver = chromium_paths()
    process, port = start_chromium(browser, profile_dir, width, height)
    try:
        options = webdriver.ChromeOptions()
        options.debugger_address = f"127.0.0.1:{port}"
        session = webdriver.Chrome(service=loopback_service(driver), options=options)
    except BaseException:
        process.kill()
        process.wait()
        raise
    quit_session = session.quit

    def quit():
        try:
            quit_session()
        finally:
            process.terminate()
            try:
                process.wait(10)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()

    session.quit = quit
    return session

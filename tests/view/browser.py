"""Headless Debian Chromium driven over the DevTools protocol (a websocket): load a page,
take screenshots, read the page's text. No browser is downloaded: without /usr/bin/chromium
(or $ARMIK_CHROMIUM) the browser tests skip."""

from __future__ import annotations

import base64
import io
import itertools
import json
import os
import shutil
import subprocess
import tempfile
import time
import urllib.request
from pathlib import Path

import numpy as np

CHROMIUM = os.environ.get("ARMIK_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
SIZE = (1200, 800)  # the window: the panel floats over the right third of the 3D view
FLAGS = [
    "--headless=new",
    # ANGLE on SwiftShader: WebGL on the CPU (this Chromium has no --use-gl=swiftshader)
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--no-sandbox",
    "--disable-gpu-sandbox",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    f"--window-size={SIZE[0]},{SIZE[1]}",
]


def available() -> str | None:
    """None if the browser tests can run, else why not (one line)."""
    if not Path(CHROMIUM).is_file():
        return f"no Chromium at {CHROMIUM} (apt-get install chromium)"
    return None


class Browser:
    """One headless Chromium with one page; ``close()`` ends the process it started."""

    def __init__(self, timeout: float = 60.0) -> None:
        from websockets.sync.client import connect

        self._profile = tempfile.mkdtemp(prefix="armik-chromium-")
        self._proc = subprocess.Popen(
            [CHROMIUM, *FLAGS, f"--user-data-dir={self._profile}", "--remote-debugging-port=0",
             "about:blank"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )  # fmt: skip
        try:
            port = self._devtools_port(timeout)
            pages = _until(lambda: _pages(port), timeout, "Chromium's page list")
            self._ws = connect(pages[0]["webSocketDebuggerUrl"], max_size=None, open_timeout=30)
        except BaseException:
            self.close()
            raise
        self._ids = itertools.count(1)

    def _devtools_port(self, timeout: float) -> int:
        marker = Path(self._profile) / "DevToolsActivePort"

        def port() -> int | None:
            if self._proc.poll() is not None:
                raise RuntimeError(f"Chromium exited with code {self._proc.returncode}")
            text = marker.read_text() if marker.exists() else ""
            return int(text.split()[0]) if text.strip() else None

        return _until(port, timeout, "Chromium's DevTools port")

    def call(self, method: str, **params) -> dict:
        """Send one DevTools command and return its result (events in between are dropped)."""
        n = next(self._ids)
        self._ws.send(json.dumps({"id": n, "method": method, "params": params}))
        while True:
            reply = json.loads(self._ws.recv(timeout=120))
            if reply.get("id") == n:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})

    def open(self, url: str, timeout: float = 60.0) -> None:
        """Navigate to ``url`` and wait until its document has loaded."""
        self.call("Page.navigate", url=url)

        def loaded() -> bool:
            try:
                href = self.evaluate("document.readyState === 'complete' && location.href")
            except RuntimeError:  # between two documents
                return False
            return bool(href) and href.startswith(url.rstrip("/"))

        _until(loaded, timeout, f"the page {url}")

    def screenshot(self) -> np.ndarray:
        """(height, width, 3) uint8 pixels of the page."""
        from PIL import Image

        data = base64.b64decode(self.call("Page.captureScreenshot", format="png")["data"])
        return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"))

    def evaluate(self, expression: str):
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True)
        return result.get("result", {}).get("value")

    def close(self) -> None:
        ws = getattr(self, "_ws", None)
        if ws is not None:
            ws.close()
        if self._proc.poll() is None:
            self._proc.terminate()
            try:
                self._proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self._proc.kill()
                self._proc.wait()
        shutil.rmtree(self._profile, ignore_errors=True)

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def poll(condition, timeout: float = 60.0, every: float = 0.5):
    """``condition()``'s first value that is neither None nor False, asking until
    ``timeout`` (s) passes; None then."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value is not None and value is not False:
            return value
        if time.monotonic() > deadline:
            return None
        time.sleep(every)


def _until(get, timeout: float, what: str):
    value = poll(get, timeout, 0.1)
    if not value:
        raise RuntimeError(f"{what} did not appear within {timeout:g} s")
    return value


def _pages(port: int) -> list[dict] | None:
    try:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10) as r:
            pages = [t for t in json.load(r) if t.get("type") == "page"]
    except OSError:
        return None
    return pages or None

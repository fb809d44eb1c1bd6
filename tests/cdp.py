"""A headless Chromium driven through the DevTools protocol over ``--remote-debugging-pipe``
(no driver, no extra package): open a page, see every request it makes, evaluate JavaScript
in it, take a screenshot.

Chromium reads commands from its fd 3 and writes answers and events to its fd 4, each a JSON
text ended by a NUL (https://chromedevtools.github.io/devtools-protocol/).
"""

from __future__ import annotations

import base64
import fcntl
import json
import os
import queue
import subprocess
import threading
import time
from pathlib import Path
from typing import Any


class DevToolsError(RuntimeError):
    pass


def _above_4(fd: int) -> int:
    """``fd`` moved to a number above 4 (so that putting it on 3 or 4 loses nothing)."""
    moved = fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10)
    os.close(fd)
    return moved


class Browser:
    """One headless Chromium with a fresh profile; ``events`` holds every event received."""

    def __init__(self, executable: str, flags: list[str], profile: Path) -> None:
        to_child, self._write = os.pipe()
        self._read, from_child = os.pipe()
        to_child, from_child = _above_4(to_child), _above_4(from_child)
        # the shell puts those pipe ends on the browser's fds 3 and 4, then becomes the browser
        redirect = f'exec "$0" "$@" 3<&{to_child} 4>&{from_child} {to_child}<&- {from_child}>&-'
        self.proc = subprocess.Popen(
            ["bash", "-c", redirect, executable, *flags, f"--user-data-dir={profile}",
             "--remote-debugging-pipe", "about:blank"],
            pass_fds=(to_child, from_child), stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        )  # fmt: skip
        os.close(to_child)
        os.close(from_child)
        self._messages: queue.Queue[dict[str, Any] | None] = queue.Queue()
        self.events: list[dict[str, Any]] = []
        self._next = 0
        threading.Thread(target=self._pump, daemon=True).start()

    def _pump(self) -> None:
        buffer = b""
        with os.fdopen(self._read, "rb", buffering=0) as pipe:
            while chunk := pipe.read(1 << 16):
                buffer += chunk
                *messages, buffer = buffer.split(b"\0")
                for m in messages:
                    self._messages.put(json.loads(m))
        self._messages.put(None)

    def call(self, method: str, params: dict[str, Any] | None = None,
             session: str | None = None, timeout: float = 60.0) -> dict[str, Any]:  # fmt: skip
        """Send a command and wait for its answer (events meanwhile go to :attr:`events`)."""
        self._next += 1
        message: dict[str, Any] = {"id": self._next, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self._write, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + timeout
        while True:
            got = self._messages.get(timeout=max(0.0, deadline - time.monotonic()))
            if got is None:
                raise DevToolsError(f"Chromium closed the pipe during {method}")
            if got.get("id") == self._next:
                if "error" in got:
                    raise DevToolsError(f"{method}: {got['error']}")
                return got.get("result", {})
            self.events.append(got)

    def open(self, url: str, width: int = 1200, height: int = 900) -> str:
        """A new tab (``width`` x ``height`` pixels) with its network recorded, at ``url`` once
        loaded; its session id."""
        target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True})[
            "sessionId"
        ]
        for domain in ("Network", "Page", "Runtime"):
            self.call(f"{domain}.enable", session=session)
        screen = {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False}
        self.call("Emulation.setDeviceMetricsOverride", screen, session)
        self.call("Page.navigate", {"url": url}, session=session)
        self.wait(session, "document.readyState === 'complete'")
        return session

    def evaluate(self, session: str, expression: str) -> Any:
        """The JSON value of a JavaScript expression in the page (promises awaited)."""
        result = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                "awaitPromise": True}, session)  # fmt: skip
        if "exceptionDetails" in result:
            raise DevToolsError(f"{expression[:80]}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def wait(self, session: str, condition: str, timeout: float = 60.0) -> None:
        deadline = time.monotonic() + timeout
        while not self.evaluate(session, f"Boolean({condition})"):
            if time.monotonic() > deadline:
                raise DevToolsError(f"timed out waiting for {condition}")
            time.sleep(0.1)

    def screenshot(self, session: str) -> bytes:
        """The tab's viewport as PNG bytes."""
        data = self.call("Page.captureScreenshot", {"format": "png"}, session)["data"]
        return base64.b64decode(data)

    def requests(self, session: str) -> list[str]:
        """The URL of every request the tab has made."""
        while True:
            try:
                got = self._messages.get_nowait()
            except queue.Empty:
                break
            if got is not None:
                self.events.append(got)
        sent = "Network.requestWillBeSent"
        return [e["params"]["request"]["url"] for e in self.events
                if e.get("sessionId") == session and e.get("method") == sent]  # fmt: skip

    def close(self) -> None:
        try:
            self.call("Browser.close", timeout=10)
        except (DevToolsError, queue.Empty, OSError):
            pass
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        os.close(self._write)

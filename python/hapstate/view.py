"""hapstate-view: a state directory in a web browser (docs/python.md, "The viewer").

A small HTTP server on 127.0.0.1 serves one page (web/index.html, web/view.js), three.js from
Debian's libjs-three, and what the page asks of the state: the surface, the workspace grid and
its check-points (catalogue, read-only), and the force and deformation at a probe position from
the C++ haptic cursor (hapstate._core.Cursor) that a device loop would use. Nothing else is
served: any other path is 404, a path with '..' (plain or percent-encoded) 400, a malformed
probe 400, a request naming another host 403.
"""

from __future__ import annotations

import argparse
import base64
import http.server
import json
import math
import pathlib
import sys
import threading
import tomllib
import urllib.parse
import webbrowser
from typing import Any, Optional

import numpy as np

from ._core import Catalogue, Cursor, InputError, Playback

_WEB = pathlib.Path(__file__).resolve().parent / "web"
# three.js r111 from Debian's libjs-three (scripts/install-deps.sh), served locally.
_THREE = pathlib.Path("/usr/share/javascript/three")
_FILES = {
    "/": (_WEB / "index.html", "text/html; charset=utf-8"),
    "/index.html": (_WEB / "index.html", "text/html; charset=utf-8"),
    "/view.js": (_WEB / "view.js", "text/javascript; charset=utf-8"),
    "/lib/three.min.js": (_THREE / "three.min.js", "text/javascript; charset=utf-8"),
    "/lib/OrbitControls.js": (_THREE / "examples/js/controls/OrbitControls.js",
                              "text/javascript; charset=utf-8"),
}
# The probe walks from its last position to a new one in steps of at most this many grid
# spacings, as a device sampled at 1 kHz would (the cursor follows transitions cell by cell).
_STEP = 0.05
# A target farther from the workspace than this many times its size is refused (400): the
# cursor extends the force outside the grid, but a walk there is no view of the state.
_REACH = 2.0


class BadRequest(ValueError):
    """A request the viewer refuses with 400 and this message."""


def parse_position(text: Optional[str], what: str = "probe") -> np.ndarray:
    """'x,y,z' -> (3,) finite floats; BadRequest naming what is wrong otherwise."""
    if text is None:
        raise BadRequest(f"{what}: missing (expected {what}=x,y,z in mesh units)")
    parts = text.split(",")
    if len(parts) != 3:
        raise BadRequest(f"{what}={text!r}: expected three numbers x,y,z")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise BadRequest(f"{what}={text!r}: not a number") from None
    if not all(math.isfinite(v) for v in values):
        raise BadRequest(f"{what}={text!r}: not finite")
    return np.array(values)


class ViewState:
    """What the page shows of one state directory: the playback file and its cursor, the
    catalogue's check-points (read once), and the scene's probe (read from the catalogue)."""

    def __init__(self, state_dir: pathlib.Path):
        self.state_dir = state_dir
        catalogue = Catalogue(state_dir)
        playback_file = state_dir / "playback.bin"
        if not playback_file.exists():
            raise InputError(f"{playback_file}: no playback file: run hapstate-index --state "
                             f"{state_dir} first")
        self.playback = Playback(playback_file)
        self.cursor: Cursor = self.playback.cursor("hermite")
        self.lock = threading.Lock()
        self.scene = self._scene(catalogue)
        self.scene_json = json.dumps(self._scene_payload(catalogue)).encode()

    @staticmethod
    def _scene(catalogue: Catalogue) -> dict[str, Any]:
        text = catalogue.query("SELECT text FROM scene")["text"]
        try:
            return tomllib.loads(text[0]) if text else {}
        except tomllib.TOMLDecodeError:
            return {}

    def _scene_payload(self, catalogue: Catalogue) -> dict[str, Any]:
        pb = self.playback
        configs = catalogue.configurations()
        points = catalogue.checkpoints()
        live = configs["status"] != 2  # merged levels are not states any more
        by_id = {int(i): n for n, i in enumerate(points["id"])}
        levels = np.zeros(len(points["id"]), dtype=np.int64)
        force = np.zeros(len(points["id"]))
        for cp, f in zip(configs["checkpoint"][live], configs["force"][live]):
            n = by_id[int(cp)]
            levels[n] += 1
            force[n] = max(force[n], float(np.linalg.norm(f)))
        stored = levels > 0
        refined = catalogue.query(
            "SELECT DISTINCT p.x, p.y, p.z FROM refinement r JOIN configuration c ON c.id = r.cell "
            "JOIN checkpoint p ON p.id = c.checkpoint")
        refined_corners = np.stack([refined[a] for a in ("x", "y", "z")], axis=1) \
            if len(refined.get("x", [])) else np.zeros((0, 3))
        summary = catalogue.summary()
        probe = self.scene.get("probe", {})
        return {
            "state": str(self.state_dir),
            "contact": bool(pb.is_contact),
            "probe_radius": float(probe.get("radius", 0.0)) if pb.is_contact else 0.0,
            "max_force": pb.max_force,
            "probe_rest": pb.probe_rest.tolist(),
            "rest_positions": pb.rest_positions.ravel().tolist(),
            "triangles": pb.triangles.ravel().tolist(),
            "grid": {"origin": pb.grid_origin.tolist(), "spacing": pb.grid_spacing.tolist(),
                     "lo": pb.grid_lo.tolist(), "dims": pb.grid_dims.tolist()},
            "checkpoints": {"position": points["position"][stored].ravel().tolist(),
                            "levels": levels[stored].tolist(),
                            "force": force[stored].tolist()},
            "refined_cells": refined_corners.ravel().tolist(),
            "certificate": summary.get("certificate"),
        }

    def move(self, target: np.ndarray, scheme: str, from_rest: bool) -> dict[str, Any]:
        """Moves the cursor to `target` in a straight line (from rest, or from where it is)."""
        if scheme not in ("hermite", "trilinear"):
            raise BadRequest(f"scheme={scheme!r}: expected hermite or trilinear")
        pb = self.playback
        lo = pb.grid_origin + pb.grid_lo * pb.grid_spacing
        size = (pb.grid_dims - 1) * pb.grid_spacing
        margin = _REACH * max(float(size.max()), float(pb.grid_spacing.max()))
        if np.any(target < lo - margin) or np.any(target > lo + size + margin):
            raise BadRequest(f"to={','.join(repr(float(x)) for x in target)}: farther from the "
                             f"workspace [{lo.tolist()}, {(lo + size).tolist()}] than "
                             f"{_REACH:g} times its size")
        with self.lock:
            if self.cursor.scheme != scheme:
                self.cursor.scheme = scheme
            start = self.cursor.probe
            if from_rest or start is None:
                self.cursor.reset()
                start = self.playback.probe_rest
            step = _STEP * float(np.min(self.playback.grid_spacing))
            n = min(100_000, max(1, int(math.ceil(float(np.linalg.norm(target - start)) / step))))
            path = start + np.outer(np.arange(1, n + 1) / n, target - start)
            force = self.cursor.force(path)[-1]
            stiffness = self.cursor.stiffness(target)
            u = self.cursor.deform().astype(np.float32)
        return {"probe": target.tolist(), "force": force.tolist(),
                "stiffness": stiffness.ravel().tolist(),
                "displacements": base64.b64encode(u.tobytes()).decode("ascii")}


class Handler(http.server.BaseHTTPRequestHandler):
    server_version = "hapstate-view"
    view: ViewState  # set on the subclass made by serve()
    quiet = False

    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 (the base's name)
        if not self.quiet:
            sys.stderr.write("hapstate-view: " + (format % args) + "\n")

    def _send(self, code: int, body: bytes, content_type: str) -> None:
        self.send_response(code)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.end_headers()
        if self.command != "HEAD":
            self.wfile.write(body)

    def _error(self, code: int, message: str) -> None:
        self._send(code, json.dumps({"error": message}).encode(), "application/json")

    def _host_ok(self) -> bool:
        host = (self.headers.get("Host") or "").rsplit(":", 1)[0].strip("[]")
        return host in ("127.0.0.1", "localhost", "::1", "")

    def do_HEAD(self) -> None:  # noqa: N802 (http.server's name)
        self.do_GET()

    def do_GET(self) -> None:  # noqa: N802
        try:
            self._get()
        except BadRequest as e:
            self._error(400, str(e))
        except Exception as e:  # noqa: BLE001 (answered, not dropped: the server goes on)
            self._error(500, f"{type(e).__name__}: {e}")

    def _get(self) -> None:
        if not self._host_ok():
            return self._error(403, "the viewer answers only requests to 127.0.0.1")
        url = urllib.parse.urlsplit(self.path)
        decoded = url.path
        for _ in range(16):  # '%252e' decodes to '%2e', then to '.': until nothing changes
            once = urllib.parse.unquote(decoded)
            if once == decoded:
                break
            decoded = once
        if ".." in decoded or "\\" in decoded or "\0" in decoded:
            raise BadRequest(f"{url.path!r}: outside the viewer's files")
        query = urllib.parse.parse_qs(url.query, keep_blank_values=True)
        one = {k: v[-1] for k, v in query.items()}
        if url.path in ("/", "/index.html") and "probe" in one:
            parse_position(one["probe"])  # a malformed link is refused, not shown broken
        if url.path in _FILES:
            file, content_type = _FILES[url.path]
            try:
                body = file.read_bytes()
            except OSError as e:
                return self._error(404, f"{file}: {e.strerror} (is libjs-three installed? "
                                        "scripts/install-deps.sh)")
            return self._send(200, body, content_type)
        if url.path == "/api/scene":
            return self._send(200, self.view.scene_json, "application/json")
        if url.path == "/api/move":
            target = parse_position(one.get("to"), "to")
            from_rest = one.get("from", "here") == "rest"
            body = self.view.move(target, one.get("scheme", "hermite"), from_rest)
            return self._send(200, json.dumps(body).encode(), "application/json")
        return self._error(404, f"{url.path!r}: no such page")

    def do_POST(self) -> None:  # noqa: N802
        self._error(405, "the viewer is read-only")

    do_PUT = do_DELETE = do_PATCH = do_POST


def serve(state_dir: pathlib.Path, port: int, quiet: bool = False):
    """The viewer's server for `state_dir` on 127.0.0.1:`port` (0: a free port), not started."""
    view = ViewState(state_dir)
    handler = type("BoundHandler", (Handler,), {"view": view, "quiet": quiet})
    server = http.server.ThreadingHTTPServer(("127.0.0.1", port), handler)
    server.daemon_threads = True
    return server


def main(argv: Optional[list[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="hapstate-view",
        description="Shows a state directory in a web browser: the organ's surface deforming as "
                    "you drag the probe (the C++ haptic cursor's force and shape), the workspace "
                    "grid and its check-points. Serves 127.0.0.1 only, read-only.")
    parser.add_argument("--state", required=True, type=pathlib.Path,
                        help="state directory (with catalogue.sqlite and playback.bin)")
    parser.add_argument("--port", type=int, default=8765,
                        help="port on 127.0.0.1 (default 8765; 0 picks a free one)")
    parser.add_argument("--no-browser", action="store_true",
                        help="do not open a browser, only print the address")
    parser.add_argument("--quiet", action="store_true", help="do not log requests")
    args = parser.parse_args(argv)
    if not 0 <= args.port <= 65535:
        parser.error(f"--port {args.port}: expected 0..65535")
    try:
        server = serve(args.state, args.port, args.quiet)
    except ValueError as e:  # hapstate.InputError is one
        print(f"hapstate-view: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"hapstate-view: {args.state}: {e}", file=sys.stderr)
        return 4
    url = f"http://127.0.0.1:{server.server_address[1]}/"
    print(f"hapstate-view: {args.state} at {url} (Ctrl-C stops)", flush=True)
    if not args.no_browser:
        webbrowser.open(url)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        server.server_close()
    return 0

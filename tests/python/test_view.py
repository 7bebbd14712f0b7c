"""hapstate-view: its server refuses what it must, and Debian's headless chromium shows the page
with the C++ cursor's force at a ?probe= position and a drawn (not blank) picture."""

import http.client
import os
import re
import subprocess
import tempfile

import numpy as np
import pytest
from matplotlib import image

import hapstate
from conftest import TOOLS

CHROMIUM = "/usr/bin/chromium"


@pytest.fixture(scope="module")
def viewer(state):
    proc = subprocess.Popen([TOOLS / "hapstate-view", "--state", state.dir, "--port", "0",
                             "--no-browser", "--quiet"], stdout=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    m = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
    assert m, line
    yield state, int(m.group(1))
    proc.terminate()
    proc.wait(timeout=10)


def get(port, path, host=None):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    c.putrequest("GET", path, skip_host=host is not None)
    if host is not None:
        c.putheader("Host", host)
    c.endheaders()
    r = c.getresponse()
    return r.status, r.read()


def inside_point(pb, state):
    """A point of the workspace where the probe presses on the body: eval's path's step with the
    largest force."""
    return state.eval.path[int(np.argmax(np.linalg.norm(state.eval.exact, axis=1)))]


def test_server_refuses_what_it_must(viewer):
    state, port = viewer
    for path in ["/../etc/passwd", "/lib/../../../etc/passwd", "/%2e%2e/etc/passwd",
                 "/lib/%2E%2E%2Fview.py", "/%252e%252e/%252e%252e/etc/passwd", "/..%5c..%5cx",
                 "/?probe=abc", "/?probe=1,2", "/?probe=1,2,3,4", "/?probe=nan,1,1",
                 "/?probe=inf,0,0", "/?probe=", "/api/move", "/api/move?to=1,x,2",
                 "/api/move?to=1,2,3&scheme=cubic", "/api/move?to=1e200,0,0",
                 "/api/move?to=0,-1e7,0", "/%2525252e%2525252e/etc/passwd"]:
        status, body = get(port, path)
        assert status == 400, (path, status, body)
        assert b"error" in body
    for path in ["/view.py", "/catalogue.sqlite", "/state/playback.bin", "/etc/passwd",
                 "/lib/three.js"]:
        assert get(port, path)[0] == 404, path
    assert get(port, "/", host="example.com")[0] == 403
    assert get(port, "/")[0] == 200
    assert get(port, "/lib/three.min.js")[0] == 200
    # Still serving after all that.
    status, body = get(port, "/api/scene")
    assert status == 200 and b"triangles" in body


def test_chromium_shows_the_cursor_force(viewer):
    state, port = viewer
    assert os.access(CHROMIUM, os.X_OK), "chromium missing: run scripts/install-deps.sh"
    pb = hapstate.Playback(state.dir)
    target = inside_point(pb, state)
    url = f"http://127.0.0.1:{port}/?probe={','.join(repr(float(x)) for x in target)}"
    with tempfile.TemporaryDirectory() as profile:
        flags = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
                 "--enable-unsafe-swiftshader", f"--user-data-dir={profile}",
                 "--window-size=900,650", "--virtual-time-budget=15000"]
        dom = subprocess.run(flags + ["--dump-dom", url], capture_output=True, text=True,
                             timeout=120).stdout
        shot = os.path.join(profile, "view.png")
        subprocess.run(flags + [f"--screenshot={shot}", url], capture_output=True, timeout=120)
        picture = image.imread(shot)
    assert 'data-ready="1"' in dom, dom[-2000:]
    assert re.search(r'<div id="error"></div>', dom), dom[-2000:]
    assert re.search(r'<span id="probe">[-0-9.e, ]+</span>', dom)
    readout = re.search(r'<span id="force">([^<]*)</span>', dom).group(1)
    shown = np.array([float(x) for x in readout.split()])
    # The server walks from rest to the target in steps of 0.05 spacing (view.py, _STEP).
    start = pb.probe_rest
    n = max(1, int(np.ceil(np.linalg.norm(target - start) / (0.05 * pb.grid_spacing.min()))))
    expected = pb.cursor().force(start + np.outer(np.arange(1, n + 1) / n, target - start))[-1]
    assert np.linalg.norm(expected) > 0
    assert np.abs(shown - expected).max() <= 1e-5 * np.linalg.norm(expected)
    # Not blank: the right half (away from the panel) holds the drawing, not only background.
    assert picture.shape[0] >= 600 and picture.shape[1] >= 800
    right = picture[:, picture.shape[1] // 2:, :3]
    background = right[0, -1]
    drawn = np.any(np.abs(right - background) > 0.05, axis=2).mean()
    assert drawn > 0.02, drawn
    assert len(np.unique((right * 255).astype(np.uint8).reshape(-1, 3), axis=0)) > 50

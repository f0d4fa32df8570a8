#!/usr/bin/env python3
"""The HTML reports of `bench shadows` and `bench stochastic` in a real browser (headless Chromium).

    browser_report_test.py PENUMBRA_BINARY WORK_DIR

Writes both reports with small settings, serves WORK_DIR on a loopback port and loads each
index.html in headless Chromium: through a checker page of the same origin that counts the report's
images, those that decoded (naturalWidth > 0) and its plots (the Pareto SVGs), and as a screenshot.
Fails when an image or plot is missing or broken, or the screenshot is blank. Exits 77 (skipped,
with a message) when Chromium is not installed.
"""
import functools
import html
import http.server
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import threading
import zlib

CHECKER = """<!doctype html><html><body>
<iframe id="f" src="%s" width="1400" height="3000"></iframe>
<script>
const f = document.getElementById("f");
f.addEventListener("load", () => {
  const d = f.contentDocument, imgs = Array.from(d.images);
  const wait = imgs.map(i => i.complete ? Promise.resolve() : new Promise(r => { i.onload = r; i.onerror = r; }));
  Promise.all(wait).then(() => {
    const broken = imgs.filter(i => !(i.naturalWidth > 0)).map(i => i.getAttribute("src"));
    const plots = imgs.filter(i => i.classList.contains("plot") && i.naturalWidth > 0).length;
    const r = {title: d.title, images: imgs.length, broken: broken, plots: plots,
               tables: d.querySelectorAll("table").length};
    document.body.setAttribute("data-result", JSON.stringify(r));
  });
});
</script></body></html>"""


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def browser(exe, profile, *args):
    cmd = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--user-data-dir=" + profile,
           "--virtual-time-budget=20000", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=180)


def png_pixels_vary(path):
    """True when the PNG's decoded rows are not all one colour (a page that drew something)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, width, height, channels = 8, b"", 0, 0, 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8, "8-bit PNG expected"
            channels = {2: 3, 6: 4, 0: 1, 4: 2}[colour]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride, prev, seen = zlib.decompress(idat), width * channels, bytearray(width * channels), set()
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        seen.update(bytes(line[i:i + channels]) for i in range(0, stride, channels * 7))
        prev = line
        if len(seen) > 50:
            return True
    return len(seen) > 50


def main():
    penumbra, work = sys.argv[1], sys.argv[2]
    exe = chromium()
    if not exe:
        print("browser test skipped: Chromium is not installed (Debian package chromium; "
              "scripts/test.sh installs it where it can)")
        return 77
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    runs = {
        "shadows": [penumbra, "bench", "shadows", "--scene", "contact", "--scene", "creature", "--technique", "pcss",
                    "--technique", "mvr", "--width", "120", "--height", "68", "--runs", "1", "--gt-samples", "64",
                    "--out", os.path.join(work, "shadows")],
        "stochastic": [penumbra, "bench", "stochastic", "--scene", "motion", "--method", "dual", "--method", "box",
                       "--spp", "4", "--width", "96", "--height", "54", "--runs", "1", "--ref-frames", "8",
                       "--out", os.path.join(work, "stochastic")],
    }
    for name, cmd in runs.items():
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
        if done.returncode != 0:
            print("FAILED: bench %s exited %d: %s" % (name, done.returncode, done.stderr.strip()))
            return 1
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=work)
    http.server.SimpleHTTPRequestHandler.log_message = lambda *a: None
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    base = "http://127.0.0.1:%d/" % server.server_address[1]
    failures = []
    with tempfile.TemporaryDirectory() as profile:
        for name in runs:
            with open(os.path.join(work, name + "-check.html"), "w") as f:
                f.write(CHECKER % (name + "/index.html"))
            dom = browser(exe, profile, "--dump-dom", base + name + "-check.html").stdout
            m = re.search(r'data-result="([^"]*)"', dom)
            if not m:
                failures.append(name + ": the checker page did not finish (no result in the DOM)")
                continue
            r = json.loads(html.unescape(m.group(1)))
            print(name, r)
            if r["images"] < 4 or r["broken"] or r["plots"] < 1 or r["tables"] < 1:
                failures.append("%s: %d images, broken %s, %d plots, %d tables" %
                                (name, r["images"], r["broken"], r["plots"], r["tables"]))
            shot = os.path.join(work, name + ".png")
            browser(exe, profile, "--window-size=1280,2000", "--screenshot=" + shot, base + name + "/index.html")
            if not os.path.exists(shot) or not png_pixels_vary(shot):
                failures.append(name + ": the screenshot is missing or blank")
    server.shutdown()
    for f in failures:
        print("FAILED:", f)
    if not failures:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

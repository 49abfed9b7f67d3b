#!/usr/bin/env python3
"""Loads a .glb in headless Chromium with three.js (index.html beside this file) and prints
what the page reports: "@meshes N", "@triangles N", "@vertices N", "@rendered ...", and
"@screenshot PATH" when --screenshot is given. Everything is served from 127.0.0.1 by a
server started here; no other network is used. Exit 0 when the page loaded the model.

usage: glb_in_browser.py MODEL.glb [--screenshot OUT.png] [--timeout SECONDS]
"""
import argparse
import http.server
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading

HERE = os.path.dirname(os.path.abspath(__file__))


def make_handler(glb, state):
    class Handler(http.server.SimpleHTTPRequestHandler):
        def __init__(self, *a, **kw):
            super().__init__(*a, directory=HERE, **kw)

        def log_message(self, *a):  # quiet: the test prints what matters
            pass

        def do_GET(self):
            if self.path == "/model.glb":
                with open(glb, "rb") as f:
                    data = f.read()
                self.send_response(200)
                self.send_header("Content-Type", "model/gltf-binary")
                self.send_header("Content-Length", str(len(data)))
                self.end_headers()
                self.wfile.write(data)
            elif self.path == "/wait":
                # Held until the page posted its result (bounded), so that the load event
                # comes after loading and rendering.
                state["done"].wait(state["timeout"])
                self.send_response(204)
                self.end_headers()
            else:
                super().do_GET()

        def do_POST(self):
            n = int(self.headers.get("Content-Length", "0"))
            state["result"] = self.rfile.read(n).decode("utf-8", "replace")
            state["done"].set()
            self.send_response(204)
            self.end_headers()

        def guess_type(self, path):
            if path.endswith(".wasm"):
                return "application/wasm"
            if path.endswith(".js"):
                return "text/javascript"
            return super().guess_type(path)

    return Handler


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        p = shutil.which(name)
        if p:
            return p
    sys.exit("glb_in_browser: no chromium on PATH (scripts/install-deps.sh installs it)")


def run_browser(url, extra, timeout):
    profile = tempfile.mkdtemp(prefix="uvmesh-chromium-")
    try:
        cmd = [chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
               "--disable-background-networking", "--disable-component-update", "--disable-sync",
               "--user-data-dir=" + profile, "--window-size=800,600",
               # WebGL without a GPU: Chromium's software rasterizer.
               "--use-angle=swiftshader", "--enable-unsafe-swiftshader"] + extra + [url]
        return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    finally:
        shutil.rmtree(profile, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("glb")
    ap.add_argument("--screenshot")
    ap.add_argument("--timeout", type=float, default=90)
    a = ap.parse_args()
    if not os.path.isfile(os.path.join(HERE, "node_modules", "three", "build", "three.module.js")):
        sys.exit("glb_in_browser: three.js is not installed (run tests/browser/install.sh)")

    state = {"done": threading.Event(), "result": None, "timeout": a.timeout}
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), make_handler(os.path.abspath(a.glb), state))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    url = "http://127.0.0.1:%d/index.html" % server.server_address[1]
    try:
        r = run_browser(url, ["--dump-dom"], a.timeout)
        m = re.search(r'<pre id="result"[^>]*>([^<]*)</pre>', r.stdout)
        dom = m.group(1) if m else None
        if state["result"] is None or dom is None:
            print("@error the page reported nothing (dom: %r)\n%s" % (dom, r.stderr[-3000:]))
            return 1
        if dom != state["result"]:
            print("@error the DOM (%r) and the posted result (%r) differ" % (dom, state["result"]))
            return 1
        for key, value in re.findall(r"(\w+)=((?:no \([^)]*\))|\S+)", dom):
            print("@%s %s" % (key, value))
        if "error=" in dom:
            return 1
        if a.screenshot:
            state["done"].clear()
            state["result"] = None
            out = os.path.abspath(a.screenshot)
            run_browser(url, ["--screenshot=" + out, "--hide-scrollbars"], a.timeout)
            if not os.path.isfile(out):
                print("@error no screenshot written")
                return 1
            print("@screenshot", out)
        return 0
    finally:
        server.shutdown()


if __name__ == "__main__":
    sys.exit(main())

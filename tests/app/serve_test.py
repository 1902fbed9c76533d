#!/usr/bin/python3
"""tests/app/serve_test.py — `aquarelle serve` in a real browser (headless Chromium via Selenium).

Usage: serve_test.py AQUARELLE SHARED_DIR OUTPUT_PARENT
Everything is written inside a fresh folder OUTPUT_PARENT/serve.XXXXXX (removed when every check
passed, kept otherwise): the saved images, the CLI's renders, the screenshots (serve_*.png) and
the latencies the page measured (latency.json). Exit status 0 when every check passed.

Checks: a WebSocket from another origin is refused; a thousand reconnects; a malformed message
gets an error, a 100 KB one closes its connection; a client that never reads keeps the server's
memory bounded while a page is served; the page loads and shows an image; moving a parameter's slider shows a new image whose
pixels equal `aquarelle render` of the page's printed command line; switching a variant, the
shown target and the style; dragging the camera; an out-of-range value is shown as an error and the server goes
on rendering; two tabs at once; Save writes a PNG whose manifest `aquarelle reproduce` calls
identical; a page without the token is refused; the stopped server is reported by the page;
panning; a scene file's art direction edited from the panel (CLI-equal, saved and reproduced, a
bad edit's error); the scene file and its model changed on disk while served (loaded again and
said so, a broken file a clear error, fixed it renders again, the server goes on).
"""
import base64
import json
import os
import shlex
import signal
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support.ui import WebDriverWait

import socket


def ws_connect(url, origin=None):
    """A WebSocket handshake by hand (the client a test needs: one that never reads, floods,
    reconnects). Returns the socket and the status line of the server's answer."""
    port = int(url.split(":")[2].split("/")[0])
    token = url.split("token=")[1]
    s = socket.create_connection(("127.0.0.1", port), timeout=30)
    key = base64.b64encode(os.urandom(16)).decode()
    origin = origin or "http://127.0.0.1:%d" % port
    s.sendall(("GET /ws?token=%s HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
               "Sec-WebSocket-Key: %s\r\nSec-WebSocket-Version: 13\r\nOrigin: %s\r\n\r\n" % (token, port, key, origin)).encode())
    resp = b""
    while b"\r\n\r\n" not in resp:
        chunk = s.recv(4096)
        if not chunk:
            break
        resp += chunk
    return s, resp.split(b"\r\n")[0].decode(errors="replace")


def ws_send(s, text):
    payload = text.encode()
    mask = os.urandom(4)
    n = len(payload)
    head = bytearray([0x81])
    if n < 126:
        head.append(0x80 | n)
    elif n < 65536:
        head += bytes([0x80 | 126]) + n.to_bytes(2, "big")
    else:
        head += bytes([0x80 | 127]) + n.to_bytes(8, "big")
    s.sendall(bytes(head) + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))


def ws_recv(s):
    """One message: (opcode, payload); (None, b"") when the server closed the connection."""
    def exact(n):
        b = b""
        while len(b) < n:
            c = s.recv(n - len(b))
            if not c:
                raise EOFError
            b += c
        return b
    try:
        opcode, data = None, b""
        while True:  # frames until FIN (a long message comes in fragments)
            h = exact(2)
            n = h[1] & 0x7F
            if n == 126:
                n = int.from_bytes(exact(2), "big")
            elif n == 127:
                n = int.from_bytes(exact(8), "big")
            if opcode is None:
                opcode = h[0] & 0x0F
            data += exact(n)
            if h[0] & 0x80:
                return opcode, data
    except (EOFError, ConnectionResetError, socket.timeout):
        return None, b""


def ws_next_text(s):
    while True:
        op, data = ws_recv(s)
        if op is None or op == 8:
            return None
        if op == 1:
            return json.loads(data)


def rss_mb(pid):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return 0


exe, shared, parent = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(parent, exist_ok=True)
work = tempfile.mkdtemp(prefix="serve.", dir=parent)
env = dict(os.environ, AQUARELLE_CACHE_DIR=os.path.join(work, "cache"))
scene = os.path.join(shared, "assets/gltf/WaterBottle/glTF/WaterBottle.gltf")
passed = failed = 0


def check(ok, what):
    global passed, failed
    if ok:
        passed += 1
        print("ok   - " + what, flush=True)
    else:
        failed += 1
        print("FAIL - " + what, flush=True)
    return ok


def start_server():
    p = subprocess.Popen([exe, "serve", scene, "--width", "320", "--height", "180", "--out-dir", os.path.join(work, "saved"), "--quiet"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    url = p.stdout.readline().strip()
    if not url.startswith("http://127.0.0.1:"):
        print(p.stderr.read())
        raise SystemExit("the server printed no URL")
    return p, url


def browser():
    o = webdriver.ChromeOptions()
    o.binary_location = "/usr/bin/chromium"
    for f in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1200,800"):
        o.add_argument(f)
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=o)


def wait_image(d, after_seq, timeout=30):
    """Waits until the page shows the image of its newest request, sent after `after_seq` (or
    shows an error): no image of an older state, and no reply still on its way, so the command
    line on the page belongs to the image on screen."""
    WebDriverWait(d, timeout).until(lambda d: d.execute_script(
        "return (window.aq.shownSeq > arguments[0] && window.aq.shownSeq === window.aq.seq) || window.aq.lastError !== ''", after_seq))


def shown_png(d, path):
    b64 = d.execute_async_script("""
        const done = arguments[0];
        const r = new FileReader();
        r.onload = () => done(r.result.split(',')[1]);
        r.readAsDataURL(window.aq.shownPng);""")
    with open(path, "wb") as f:
        f.write(base64.b64decode(b64))


def cli_equal(d, name):
    """The shown image against `aquarelle render` of the page's command line: same pixels."""
    if d.execute_script("return window.aq.shownFormat") != "png":
        print("the image on screen is not the still PNG")
        return False
    live = os.path.join(work, name + "_live.png")
    shown_png(d, live)
    cmd = shlex.split(d.find_element(By.ID, "command").get_attribute("value"))
    assert cmd[0] == "aquarelle" and cmd[-2] == "--out"
    cli = os.path.join(work, name + "_cli.png")
    r = subprocess.run([exe] + cmd[1:-1] + [cli, "--quiet"], env=env, capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stderr)
        return False
    c = subprocess.run([exe, "compare", live, cli], capture_output=True, text=True)
    fields = dict(l.split(None, 1) for l in c.stdout.splitlines() if l.strip())
    return c.returncode == 0 and fields.get("max_abs", "").split()[0] == "0" and fields.get("size") == "320x180x3"


server, url = start_server()
d = None
try:
    # No token, a wrong token: refused.
    base = url.split("?")[0]
    for bad in (base, base + "?token=0"):
        try:
            urllib.request.urlopen(bad, timeout=5)
            check(False, "a page without the right token is refused")
        except urllib.error.HTTPError as e:
            check(e.code == 403, "a page without the right token is refused (%d)" % e.code)

    # The WebSocket from another origin: refused.
    s, status = ws_connect(url, origin="http://evil.example")
    check(" 403 " in status, "a WebSocket from another origin is refused (%s)" % status)
    s.close()
    # A thousand reconnects: the server goes on.
    t0 = time.time()
    ok = 0
    for i in range(1000):
        s, status = ws_connect(url)
        ok += " 101 " in status
        s.close()
    check(ok == 1000, "a thousand reconnects accepted and closed (%d in %.1f s)" % (ok, time.time() - t0))
    # Malformed and oversized messages: an error reply, then the connection is closed for the
    # oversized one; the server goes on.
    s, _ = ws_connect(url)
    ws_send(s, "{not json")
    msg = ws_next_text(s)
    while msg is not None and msg.get("type") != "error":
        msg = ws_next_text(s)
    check(msg is not None and "not JSON" in msg["message"], "a malformed message gets an error reply")
    s.settimeout(10)
    t0 = time.time()
    ws_send(s, "x" * 100000)
    op = 1
    while op not in (None, 8):  # a close frame or the end of the stream; None also on the timeout
        op, _ = ws_recv(s)
    check(time.time() - t0 < 5, "a 100 KB message closes that connection (%.2f s)" % (time.time() - t0))
    s.close()
    # A client that never reads: renders requested, images never read; memory stays bounded
    # (two images queued at most) while the page below is served.
    lazy, _ = ws_connect(url)
    for i in range(60):
        ws_send(lazy, json.dumps({"type": "render", "seq": i, "state": {"params": {"edge_darken.intensity": 1 + (i % 10) * 0.1}}}))
        time.sleep(0.02)

    d = browser()
    d.get(url)
    WebDriverWait(d, 30).until(lambda d: d.execute_script("return !!window.aq && window.aq.schema !== null && document.getElementById('view').naturalWidth > 0"))
    check(True, "the page loads and shows an image")
    schema = d.execute_script("return window.aq.schema")
    ids = [s["id"] for s in schema["steps"]]
    check("edge_darken" in ids and "bleed" in ids, "the panel lists the style's steps (%d)" % len(ids))
    d.save_screenshot(os.path.join(work, "serve_page.png"))

    # Move a slider: edge_darken.intensity, dragged with the mouse.
    folder = [e for e in d.find_elements(By.CSS_SELECTOR, ".lil-gui .lil-title") if "edge_darken —" in e.text][0]
    folder.click()
    slider = d.find_element(By.CSS_SELECTOR, "[data-param='edge_darken.intensity'] .lil-slider")
    WebDriverWait(d, 10).until(lambda d: slider.is_displayed())  # the folder opens with a transition
    seq = d.execute_script("return window.aq.seq")
    ActionChains(d).click_and_hold(slider).move_by_offset(30, 0).release().perform()
    wait_image(d, seq)
    params = d.execute_script("return window.aq.state.params")
    check("edge_darken.intensity" in params, "the slider changed edge_darken.intensity (%s)" % params.get("edge_darken.intensity"))
    check(d.execute_script("return window.aq.lastError") == "", "no error after the slider")
    check(cli_equal(d, "slider"), "the shown image has the pixels of `aquarelle render` of the printed command line")

    # A parameter with named values is a list: edge_detect.border, clamp -> mirror.
    folder = [e for e in d.find_elements(By.CSS_SELECTOR, ".lil-gui .lil-title") if "edge_detect —" in e.text][0]
    folder.click()
    shown = d.find_element(By.CSS_SELECTOR, "[data-param='edge_detect.border'] .lil-display")
    WebDriverWait(d, 10).until(lambda d: shown.is_displayed())  # lil-gui draws the list over a clear <select>
    select = d.find_element(By.CSS_SELECTOR, "[data-param='edge_detect.border'] select")
    options = [o.get_attribute("textContent") for o in select.find_elements(By.TAG_NAME, "option")]
    check(options == ["clamp", "mirror"], "edge_detect.border lists its names (%s)" % options)
    seq = d.execute_script("return window.aq.seq")
    # What choosing an entry does: the <select>'s value and its change event.
    d.execute_script("const s = arguments[0]; s.selectedIndex = 1; s.dispatchEvent(new Event('change'));", select)
    wait_image(d, seq)
    border = d.execute_script("return window.aq.state.params")["edge_detect.border"]
    check(border == 1, "choosing mirror sets edge_detect.border to 1 (%s)" % border)
    check(cli_equal(d, "named"), "the image of a named value has the pixels of the printed command line")

    # Switch a variant: bleed to its other registered variant.
    bleed = [s for s in schema["steps"] if s["id"] == "bleed"][0]
    other = [v["name"] for v in bleed["variants"] if v["name"] != bleed["variant"]][0]
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.state.variants.bleed = arguments[0]; window.aq.render(true);", other)
    wait_image(d, seq)
    check(d.execute_script("return window.aq.schema.steps.find(s => s.id === 'bleed').variant") == other,
          "switching bleed to %s rebuilds the panel" % other)
    check(cli_equal(d, "variant"), "the variant's image equals the CLI's")

    # Switch the shown target.
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.state.target = 'depth.linear'; window.aq.render();")
    wait_image(d, seq)
    check(d.execute_script("return window.aq.lastError") == "", "the target depth.linear is shown")
    d.execute_script("window.aq.state.target = 'final';")

    # Drag the camera.
    view = d.find_element(By.ID, "view")
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.formats = [];")
    ActionChains(d).click_and_hold(view).move_by_offset(60, 20).pause(0.3).move_by_offset(60, 0).pause(0.3).release().perform()
    wait_image(d, seq)
    formats = d.execute_script("return window.aq.formats")
    check("jpeg" in formats and formats[-1] == "png", "while dragging the page shows previews, then the still PNG (%s)" % formats)
    v = d.execute_script("return window.aq.state.view")
    check(v[0] != 0 and v[1] != 0, "dragging turned the camera (%s)" % v)
    check(cli_equal(d, "camera"), "the turned camera's image equals the CLI's (--view)")
    d.save_screenshot(os.path.join(work, "serve_camera.png"))
    # Pan: shift-drag moves the view in its own plane.
    seq = d.execute_script("return window.aq.seq")
    ActionChains(d).key_down(Keys.SHIFT).click_and_hold(view).move_by_offset(-40, 25).release().key_up(Keys.SHIFT).perform()
    wait_image(d, seq)
    v = d.execute_script("return window.aq.state.view")
    check(len(v) == 5 and v[3] > 0 and v[4] > 0, "shift-dragging panned the camera (%s)" % v)
    check(cli_equal(d, "pan"), "the panned camera's image equals the CLI's (--view Y,P,Z,X,V)")

    # An out-of-range value: an error on the page, and the server renders the next change.
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.state.params['edge_darken.intensity'] = 999; window.aq.render();")
    WebDriverWait(d, 30).until(lambda d: d.execute_script("return window.aq.lastError !== ''"))
    err = d.execute_script("return window.aq.lastError")
    check("edge_darken" in err and "999" in err, "an out-of-range value is shown as an error: " + err[:120])
    d.save_screenshot(os.path.join(work, "serve_error.png"))
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.lastError = ''; window.aq.state.params['edge_darken.intensity'] = 2; window.aq.render();")
    wait_image(d, seq)
    check(d.execute_script("return window.aq.lastError") == "" and d.execute_script("return window.aq.shownSeq") > seq,
          "the server renders again after the error")

    # Latency of parameter changes as the browser measures it (change sent -> image decoded).
    d.execute_script("window.aq.latencies = [];")
    for i in range(12):
        seq = d.execute_script("return window.aq.seq")
        d.execute_script("window.aq.state.params['edge_darken.intensity'] = arguments[0]; window.aq.render();", 1.0 + 0.1 * i)
        wait_image(d, seq)
    lat = d.execute_script("return window.aq.latencies")
    with open(os.path.join(work, "latency.json"), "w") as f:
        json.dump({"size": "320x180", "latencies_ms": lat}, f)
    check(len(lat) == 12, "12 changes, 12 images: median %.0f ms, max %.0f ms (320x180)" % (statistics.median(lat), max(lat)))

    # Two tabs at once: the second gets its own state and images; the first is untouched.
    first = d.current_window_handle
    d.switch_to.new_window("tab")
    d.get(url)
    WebDriverWait(d, 30).until(lambda d: d.execute_script("return !!window.aq && window.aq.schema !== null && document.getElementById('view').naturalWidth > 0"))
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.state.params['edge_darken.intensity'] = 0.5; window.aq.render();")
    wait_image(d, seq)
    check(d.execute_script("return window.aq.lastError") == "", "a second tab renders its own state")
    second = d.current_window_handle
    d.switch_to.window(first)
    check(d.execute_script("return window.aq.state.params['edge_darken.intensity']") == 2.9 or
          d.execute_script("return window.aq.connected"), "the first tab is still connected")
    d.switch_to.window(second)
    d.close()
    d.switch_to.window(first)

    # Another style (its preset is read by this server process), then Save.
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.state = {style: 'mnpr', target: 'final', frame: 0, view: [0, 0, 1], variants: {}, params: {}}; window.aq.render(true);")
    wait_image(d, seq)
    check(d.execute_script("return window.aq.schema.style") == "mnpr" and d.execute_script("return window.aq.lastError") == "",
          "switching the style to mnpr rebuilds the panel")

    # Save: PNG, manifest and state in --out-dir; reproduce says identical.
    d.execute_script("document.getElementById('save').click();")
    WebDriverWait(d, 60).until(lambda d: d.find_element(By.ID, "saved").text.startswith("saved"))
    png = os.path.join(work, "saved", "aquarelle_0001.png")
    check(os.path.exists(png) and os.path.exists(png + ".json") and os.path.exists(os.path.join(work, "saved", "aquarelle_0001.state.json")),
          "Save wrote the PNG, its manifest and the state")
    r = subprocess.run([exe, "reproduce", png + ".json", "--quiet"], capture_output=True, text=True, env=env)
    check(r.returncode == 0 and "identical" in r.stdout, "reproduce of the saved image: " + (r.stdout.strip() or r.stderr.strip())[:100])

    check(rss_mb(server.pid) < 1500, "the server's memory with a client that never reads: %.0f MB" % rss_mb(server.pid))
    lazy.close()

    # The server stops: the page says so.
    server.send_signal(signal.SIGTERM)
    server.wait(timeout=10)
    WebDriverWait(d, 30).until(lambda d: not d.execute_script("return window.aq.connected"))
    check("server stopped" in d.find_element(By.ID, "status").text, "the page says the server stopped")
    d.save_screenshot(os.path.join(work, "serve_stopped.png"))
finally:
    if d is not None:
        d.quit()
    if server.poll() is None:
        server.kill()

# A scene file's art direction edited from the page, then the file changed on disk while served.
wb = os.path.join(work, "wb")
os.makedirs(wb)
src = os.path.join(shared, "assets/gltf/WaterBottle/glTF")
for f in os.listdir(src):
    with open(os.path.join(src, f), "rb") as a, open(os.path.join(wb, f), "wb") as b:
        b.write(a.read())
scene_file = {"gltf": "WaterBottle.gltf", "scale": 40.0, "camera": "auto",
              "lights": [{"direction": [-0.5, 0.6, 0.6], "intensity": 1.0}],
              "control": [{"target": "pigment.density", "source": "noise", "noise": {"frequency": 25.0, "amplitude": 0.8, "seed": 11}}],
              "materials": {"*": {"cangiante": 0.3, "shade_color": [0.1, 0.1, 0.3]}}}
scene = os.path.join(wb, "bottle.json")
with open(scene, "w") as f:
    json.dump(scene_file, f)
server, url = start_server()
d = None
try:
    d = browser()
    d.get(url)
    WebDriverWait(d, 30).until(lambda d: d.execute_script("return !!window.aq && window.aq.schema !== null && document.getElementById('view').naturalWidth > 0"))
    knobs = {k["pointer"]: k for k in d.execute_script("return window.aq.schema.scene")}
    check({"/lights/0/intensity", "/control/0/noise/frequency", "/materials/*/cangiante", "/materials/*/shade_color"} <= set(knobs)
          and knobs["/materials/*/shade_color"]["kind"] == "color",
          "the panel lists the scene file's art direction (%d values)" % len(knobs))
    # Type a new value into the scene panel's field: the image is the CLI's with --scene-set.
    top = [e for e in d.find_elements(By.CSS_SELECTOR, ".lil-gui .lil-title") if e.text.startswith("scene file")][0]
    top.click()
    group = [e for e in d.find_elements(By.CSS_SELECTOR, ".lil-gui .lil-title") if e.text.startswith("control[0]")][0]
    WebDriverWait(d, 10).until(lambda d: group.is_displayed())
    group.click()
    field = d.find_element(By.CSS_SELECTOR, "[data-scene='/control/0/noise/frequency'] input")
    WebDriverWait(d, 10).until(lambda d: field.is_displayed())
    seq = d.execute_script("return window.aq.seq")
    field.click()
    field.send_keys(Keys.CONTROL + "a")
    field.send_keys("12.5" + Keys.ENTER)
    wait_image(d, seq)
    edited = d.execute_script("return window.aq.state.scene")
    check(edited.get("/control/0/noise/frequency") == 12.5 and d.execute_script("return window.aq.lastError") == "",
          "typing into the scene panel edits the control rule (%s)" % edited)
    check("--scene-set /control/0/noise/frequency=12.5" in d.find_element(By.ID, "command").get_attribute("value"),
          "the command line carries the edit")
    check(cli_equal(d, "scene_edit"), "the edited scene's image equals the CLI's (--scene-set)")
    d.save_screenshot(os.path.join(work, "serve_scene.png"))
    # A colour and a second edit, then Save: reproduce says identical.
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.state.scene['/materials/*/shade_color'] = [0.4, 0.1, 0.05]; window.aq.render();")
    wait_image(d, seq)
    check(cli_equal(d, "scene_colour"), "an edited colour's image equals the CLI's")
    d.execute_script("document.getElementById('save').click();")
    WebDriverWait(d, 60).until(lambda d: d.find_element(By.ID, "saved").text.startswith("saved"))
    png = d.find_element(By.ID, "saved").text.split()[1]
    r = subprocess.run([exe, "reproduce", png + ".json", "--quiet"], capture_output=True, text=True, env=env)
    check(r.returncode == 0 and "identical" in r.stdout, "reproduce of a saved edited scene: " + (r.stdout.strip() or r.stderr.strip())[:100])
    # An edit the file cannot take: the reader's message on the page.
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.state.scene['/control/0/noise/frequency'] = -5; window.aq.render();")
    WebDriverWait(d, 30).until(lambda d: d.execute_script("return window.aq.lastError !== ''"))
    check("frequency" in d.execute_script("return window.aq.lastError"), "a bad edit is the reader's error: " +
          d.execute_script("return window.aq.lastError")[:100])
    d.execute_script("window.aq.lastError = ''; window.aq.state.scene['/control/0/noise/frequency'] = 12.5;")

    # The file changes on disk: the next change loads it again (the page says so, the panel shows
    # the new values); a file that no longer loads is a clear error; fixed, it renders again.
    scene_file["lights"][0]["intensity"] = 0.6
    with open(scene, "w") as f:
        json.dump(scene_file, f)
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.render();")
    wait_image(d, seq)
    check("changed on disk" in d.execute_script("return window.aq.notice") and
          [k for k in d.execute_script("return window.aq.schema.scene") if k["pointer"] == "/lights/0/intensity"][0]["value"] == 0.6,
          "a scene file changed on disk is loaded again and the page says so")
    check(cli_equal(d, "reloaded"), "the reloaded scene's image equals the CLI's")
    with open(scene, "w") as f:
        f.write("{ this is no longer a scene file")
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.render();")
    WebDriverWait(d, 30).until(lambda d: d.execute_script("return window.aq.lastError !== ''"))
    err = d.execute_script("return window.aq.lastError")
    check("changed on disk" in err and "bottle.json" in err, "a scene file broken on disk is a clear error: " + err[:120])
    with open(scene, "w") as f:
        json.dump(scene_file, f)
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.lastError = ''; window.aq.render();")
    wait_image(d, seq)
    check(d.execute_script("return window.aq.lastError") == "" and d.execute_script("return window.aq.shownSeq") > seq,
          "fixed on disk, the scene renders again")
    # The model changes on disk (a file the scene file reads): loaded again too.
    with open(os.path.join(wb, "WaterBottle.gltf"), "w") as f:
        f.write("{ this is no longer glTF")
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.render();")
    WebDriverWait(d, 30).until(lambda d: d.execute_script("return window.aq.lastError !== ''"))
    check("WaterBottle.gltf" in d.execute_script("return window.aq.lastError"), "a model broken on disk is a clear error naming it")
    seq = d.execute_script("return window.aq.seq")
    d.execute_script("window.aq.lastError = ''; window.aq.render();")
    WebDriverWait(d, 30).until(lambda d: d.execute_script("return window.aq.lastError !== ''"))
    check(server.poll() is None, "the server goes on serving")
finally:
    if d is not None:
        d.quit()
    server.terminate()
    server.wait(timeout=10)

print("serve: %d passed, %d failed" % (passed, failed))
if failed == 0 and not os.environ.get("AQ_KEEP_TEST_OUTPUT"):
    import shutil
    shutil.rmtree(work, ignore_errors=True)
else:
    print("serve: outputs kept in " + work)
sys.exit(1 if failed else 0)

#!/usr/bin/env python3
"""The page's budgets in real time (BENCHMARKS.md): Chromium headless on SwiftShader, driven through
its DevTools protocol over a pipe (no virtual time, no extra Python package). Prints, per scene,
when the first frame was drawn since navigation began and the median frame time (each frame drawn
to completion) over N frames.

    python3 web/bench.py http://127.0.0.1:8000 [frames]
"""
import json, os, subprocess, sys, tempfile, time

base = sys.argv[1].rstrip('/')
frames = int(sys.argv[2]) if len(sys.argv) > 2 else 100
chromium = os.environ.get('TUTORIAL13_CHROMIUM', 'chromium')

def run(scene):
    to_browser_r, to_browser_w = os.pipe()
    from_browser_r, from_browser_w = os.pipe()
    profile = tempfile.mkdtemp()
    # The protocol pipe is the child's fds 3 (in) and 4 (out).
    def fds():
        # Through fresh numbers first, in case the pipes already sit on 3 or 4.
        a, b = os.dup(to_browser_r), os.dup(from_browser_w)
        os.dup2(a, 3)
        os.dup2(b, 4)
    browser = subprocess.Popen(
        [chromium, '--headless=new', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
         '--no-sandbox', '--no-first-run', '--hide-scrollbars', '--window-size=1024,768',
         f'--user-data-dir={profile}', '--remote-debugging-pipe', 'about:blank'],
        preexec_fn=fds, stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL, close_fds=False)
    os.close(to_browser_r); os.close(from_browser_w)
    out = os.fdopen(to_browser_w, 'wb', buffering=0)
    inp = os.fdopen(from_browser_r, 'rb', buffering=0)
    pending = b''
    ident = [0]
    def call(method, params=None, session=None):
        nonlocal pending
        ident[0] += 1
        message = {'id': ident[0], 'method': method, 'params': params or {}}
        if session:
            message['sessionId'] = session
        out.write(json.dumps(message).encode() + b'\0')
        while True:
            while b'\0' not in pending:
                pending += inp.read(65536)
            line, pending = pending.split(b'\0', 1)
            reply = json.loads(line)
            if reply.get('id') == ident[0]:
                return reply.get('result', reply.get('error'))
    try:
        target = call('Target.createTarget', {'url': 'about:blank'})['targetId']
        session = call('Target.attachToTarget', {'targetId': target, 'flatten': True})['sessionId']
        call('Page.navigate', {'url': f'{base}/index.html?scene={scene}&panel=off&frames={frames}'}, session)
        deadline = time.time() + 120
        while time.time() < deadline:
            got = call('Runtime.evaluate', {'expression':
                'JSON.stringify([document.getElementById("canvas").dataset,'
                ' document.getElementById("message").className == "error"'
                ' ? document.getElementById("message").textContent : ""])', 'returnByValue': True}, session)
            if 'value' not in got.get('result', {}):
                time.sleep(0.05)  # still navigating: no canvas yet
                continue
            data, message = json.loads(got['result']['value'])
            if message.strip():
                return f'{scene}: the page says: {message}'
            if int(data.get('frames', 0)) >= frames:
                return (f'{scene}: first frame {data["firstFrameMs"]} ms after navigation began; '
                        f'{data["frameMs"]} ms/frame (median of {frames}, each to a one-texel read-back)')
            time.sleep(0.05)
        return f'{scene}: no {frames} frames within 120 s'
    finally:
        browser.kill()
        browser.wait()

for scene in ['cylinder', 'sprite', 'cube', 'wall']:
    print(run(scene), flush=True)

#!/usr/bin/env python3
"""The page in Chromium headless (SwiftShader's WebGL2), driven through its DevTools protocol over
a pipe in real time: no virtual time, which runs a page's timers ahead of a Web Worker's work, and
no extra Python package. web/bench.py times the page with it; the browser tests that wait for the
page (tests/all/web.rs: a bake in the page's worker) run it as a command:

    python3 web/page.py URL CONDITION OUT [SECONDS]

loads URL in a 1024×768 viewport, waits until the JavaScript expression CONDITION is true, then
writes OUT/page.png (the viewport) and OUT/dom.html (the page's HTML then). Exit 1, with a line,
if CONDITION is not true within SECONDS (default 240).
"""
import base64, json, os, subprocess, sys, tempfile, time

CHROMIUM = os.environ.get('TUTORIAL13_CHROMIUM', 'chromium')


class Page:
    """One Chromium with one tab at `url`."""

    def __init__(self, url):
        to_browser_r, to_browser_w = os.pipe()
        from_browser_r, from_browser_w = os.pipe()
        self.profile = tempfile.TemporaryDirectory(ignore_cleanup_errors=True)

        # The protocol pipe is the child's fds 3 (in) and 4 (out).
        def fds():
            # Through fresh numbers first, in case the pipes already sit on 3 or 4.
            a, b = os.dup(to_browser_r), os.dup(from_browser_w)
            os.dup2(a, 3)
            os.dup2(b, 4)
        self.browser = subprocess.Popen(
            [CHROMIUM, '--headless=new', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
             '--no-sandbox', '--no-first-run', '--hide-scrollbars', '--window-size=1024,768',
             f'--user-data-dir={self.profile.name}', '--remote-debugging-pipe', 'about:blank'],
            preexec_fn=fds, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL, close_fds=False)
        os.close(to_browser_r)
        os.close(from_browser_w)
        self.out = os.fdopen(to_browser_w, 'wb', buffering=0)
        self.inp = os.fdopen(from_browser_r, 'rb', buffering=0)
        self.pending = b''
        self.ident = 0
        self.session = None
        target = self.call('Target.createTarget', {'url': 'about:blank'})['targetId']
        self.session = self.call('Target.attachToTarget',
                                 {'targetId': target, 'flatten': True})['sessionId']
        self.call('Emulation.setDeviceMetricsOverride',
                  {'width': 1024, 'height': 768, 'deviceScaleFactor': 1, 'mobile': False})
        self.call('Page.navigate', {'url': url})

    def call(self, method, params=None):
        """The protocol's answer to `method` (its result, or its error)."""
        self.ident += 1
        message = {'id': self.ident, 'method': method, 'params': params or {}}
        if self.session:
            message['sessionId'] = self.session
        self.out.write(json.dumps(message).encode() + b'\0')
        while True:
            while b'\0' not in self.pending:
                read = self.inp.read(65536)
                if not read:
                    raise RuntimeError('Chromium closed its end of the protocol pipe')
                self.pending += read
            line, self.pending = self.pending.split(b'\0', 1)
            reply = json.loads(line)
            if reply.get('id') == self.ident:
                return reply.get('result', reply.get('error'))

    def evaluate(self, expression):
        """`expression`'s value in the page, or None while it has none (still navigating)."""
        got = self.call('Runtime.evaluate', {'expression': expression, 'returnByValue': True})
        return got.get('result', {}).get('value')

    def wait(self, condition, seconds):
        """Whether `condition` (JavaScript) came true within `seconds`, polled every 50 ms."""
        deadline = time.time() + seconds
        while time.time() < deadline:
            if self.evaluate(f'!!({condition})'):
                return True
            time.sleep(0.05)
        return False

    def screenshot(self, path):
        shot = self.call('Page.captureScreenshot', {'format': 'png'})
        with open(path, 'wb') as f:
            f.write(base64.b64decode(shot['data']))

    def close(self):
        # Browser.close ends the browser's child processes too; a kill of the main one alone left
        # them writing into the profile while it was being removed ("Directory not empty").
        try:
            self.out.write(json.dumps({'id': self.ident + 1, 'method': 'Browser.close'}).encode() + b'\0')
            self.browser.wait(timeout=10)
        except (OSError, subprocess.TimeoutExpired):
            self.browser.kill()
            self.browser.wait()
        self.profile.cleanup()


def main():
    url, condition, out = sys.argv[1:4]
    seconds = float(sys.argv[4]) if len(sys.argv) > 4 else 240
    page = Page(url)
    try:
        if not page.wait(condition, seconds):
            print(f'page.py: {condition} not true within {seconds:.0f} s', file=sys.stderr)
            sys.exit(1)
        page.screenshot(os.path.join(out, 'page.png'))
        with open(os.path.join(out, 'dom.html'), 'w') as f:
            f.write(page.evaluate('document.documentElement.outerHTML'))
    finally:
        page.close()


if __name__ == '__main__':
    main()

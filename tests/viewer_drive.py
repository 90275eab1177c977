#!/usr/bin/env python3
"""Drives the viewer as a user would, for tests/viewer_test.sh: loads the interactive page in
chromium-headless-shell, drags model A's first slider with the mouse (DevTools protocol over
--remote-debugging-pipe: fds 3 and 4, NUL-terminated JSON; no websocket library needed), waits
until the page has rebuilt its row, and writes the new spec on stdout and the row's beam sphere
(read back from a float framebuffer, as the test mode does) into OUT as <pre id="result">JSON</pre>
for tests/viewer_compare.cpp.

Usage: viewer_drive.py BROWSER URL OUT SIZE
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

TIMEOUT_SECONDS = 60  # bakes on a loaded 2-core machine take seconds; a hang fails the test


class Browser:
    def __init__(self, binary, profile):
        to_browser_r, self.to_browser = os.pipe()
        self.from_browser, from_browser_w = os.pipe()

        # The browser reads commands on fd 3 and answers on fd 4: the shell moves the pipes there
        # (the parent's own ends may already occupy 3 and 4).
        self.process = subprocess.Popen(
            ['sh', '-c', f'exec "$@" 3<&{to_browser_r} 4>&{from_browser_w}', 'sh', binary, '--no-sandbox',
             '--headless', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--remote-debugging-pipe',
             # no background connections (tests/harness.sh, CHROMIUM_FLAGS)
             '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run',
             '--disable-quic',
             '--window-size=1400,1100', f'--user-data-dir={profile}', 'about:blank'],
            pass_fds=(to_browser_r, from_browser_w), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            start_new_session=True)  # its own process group: close() stops the helpers too
        os.close(to_browser_r)
        os.close(from_browser_w)
        self.buffer = b''
        self.next_id = 0
        self.session = None

    def call(self, method, **params):
        self.next_id += 1
        message = {'id': self.next_id, 'method': method, 'params': params}
        if self.session:
            message['sessionId'] = self.session
        os.write(self.to_browser, json.dumps(message).encode() + b'\0')
        while True:
            while b'\0' not in self.buffer:
                chunk = os.read(self.from_browser, 1 << 16)
                if not chunk:
                    raise RuntimeError('the browser closed its pipe')
                self.buffer += chunk
            raw, self.buffer = self.buffer.split(b'\0', 1)
            reply = json.loads(raw)
            if reply.get('id') == self.next_id:
                if 'error' in reply:
                    raise RuntimeError(f'{method}: {reply["error"]}')
                return reply['result']

    def evaluate(self, expression):
        result = self.call('Runtime.evaluate', expression=expression, awaitPromise=True, returnByValue=True)
        if 'exceptionDetails' in result:
            raise RuntimeError(f'{expression[:60]}...: {result["exceptionDetails"]}')
        return result['result'].get('value')

    def wait_for(self, expression, what, timeout_seconds=TIMEOUT_SECONDS):
        deadline = time.monotonic() + timeout_seconds
        while time.monotonic() < deadline:
            value = self.evaluate(expression)
            if value:
                return value
            time.sleep(0.1)
        raise RuntimeError(f'timed out waiting for {what}')

    def open(self, url, timeout_seconds=TIMEOUT_SECONDS):
        """A new tab on `url`, attached to, once the page says it is ready."""
        target = self.call('Target.createTarget', url='about:blank')['targetId']
        self.session = self.call('Target.attachToTarget', targetId=target, flatten=True)['sessionId']
        self.call('Page.navigate', url=url)
        self.wait_for('document.getElementById("result")?.textContent.includes("ready")', 'the page', timeout_seconds)

    def mouse(self, kind, x, y):
        self.call('Input.dispatchMouseEvent', type=kind, x=x, y=y, button='left', clickCount=1)

    def close(self):
        # The browser's helper processes (renderer, GPU, network) share its process group; killing
        # the main process alone leaves them writing into the profile while it is being removed.
        try:
            os.killpg(self.process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.process.wait()
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            try:
                os.killpg(self.process.pid, 0)
            except ProcessLookupError:
                break
            time.sleep(0.05)


def profile_directory():
    """The browser's temporary profile; a helper that outlives close() (reparented, unreaped) must not
    turn a finished run into a failure while the directory is removed."""
    return tempfile.TemporaryDirectory(ignore_cleanup_errors=True)


def main():
    binary, url, out, size = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
    with profile_directory() as profile:
        browser = Browser(binary, profile)
        try:
            browser.open(url)
            before = browser.evaluate('document.getElementById("spec-a").value')
            builds = browser.evaluate('state.builds')
            # The slider: press on its thumb, drag to the middle of its track, release.
            box = browser.evaluate('(() => { const r = document.querySelector("#sliders-a input[type=range]")'
                                   '.getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; })()')
            position = browser.evaluate('Number(document.querySelector("#sliders-a input[type=range]").value) / 1000')
            y = box[1] + box[3] / 2
            start = box[0] + 8 + position * (box[2] - 16)  # the thumb (16 px wide) at the value
            browser.mouse('mousePressed', start, y)
            for k in range(1, 11):
                browser.mouse('mouseMoved', start + k * (box[0] + 0.5 * box[2] - start) / 10, y)
            browser.mouse('mouseReleased', box[0] + 0.5 * box[2], y)
            browser.wait_for(f'state.builds > {builds}', 'the rebuilt row')
            after = browser.evaluate('document.getElementById("spec-a").value')
            field = browser.evaluate(
                f'(() => {{ const f = state.rows[0].shading.readField(0, state.light, {size});'
                f' return {{webgl2: true, width: {size}, height: {size}, value: Array.from(f.value),'
                f' mask: Array.from(f.mask)}}; }})()')
        finally:
            browser.close()
    with open(out, 'w') as file:
        file.write('<pre id="result">' + json.dumps(field) + '</pre>\n')
    print(json.dumps({'before': before, 'after': after}))


if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""`ganzfeld serve` against hostile and careless clients (docs/serve.md, "Limits"): slow heads
(slowloris), clients that never read, expensive work whose client leaves, SIGTERM during an endless
bake, Range, request bodies, pipelining, a tampered cache file, bad numbers, Host, paths in errors.
Every probe runs on 127.0.0.1, with a bounded number of connections and a bounded time (about a
minute in all); each one failed against the service before it was hardened.

Usage: serve_hostile_test.py PATH/TO/ganzfeld PATH/TO/exr_nudge
"""
import http.client
import json
import os
import re
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

G, NUDGE = sys.argv[1], sys.argv[2]
TMP = tempfile.mkdtemp(prefix="serve_hostile-")
passed, failed = 0, 0

# A mixture of 16 narrow lobes at a tolerance no budget meets: minutes of work per value.
EXPENSIVE_SPEC = "%2B".join(["hvd-fit:r1=1e-6,n1=1e6"] * 16)
EXPENSIVE_EVAL = f"/api/eval?model={EXPENSIVE_SPEC}&law=g&theta_i=30&theta_j=40&tol=1e-15"
ENDLESS_BAKE = f"/api/table?model={EXPENSIVE_SPEC}&law=g&res=64x64x64&tol=1e-15"
# A table whose JSON is about 330 kB: far more than a non-reading client's socket buffers take.
BIG_JSON = "/api/table?model=minnaert:xi=1&law=h&res=16384&tol=1e-6&format=json"
CACHED = "/api/table?model=minnaert:xi=1&law=h&res=32"
PROMPT = 3.0  # seconds: an answer that takes longer while others misbehave counts as starved


def check(ok, what):
    global passed, failed
    if ok:
        passed += 1
    else:
        failed += 1
        print("FAIL:", what, flush=True)


class Server:
    def __init__(self, name, *args, cache=None):
        self.log = os.path.join(TMP, name + ".log")
        self.cache = cache or os.path.join(TMP, name + "-cache")
        self.proc = subprocess.Popen([G, "serve", "--cache", self.cache, "--port", "0", *args],
                                     stderr=open(self.log, "w"))
        self.port = None
        for _ in range(200):
            m = re.search(r"listening on http://127\.0\.0\.1:(\d+)/", open(self.log).read())
            if m:
                self.port = int(m.group(1))
                break
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        if self.port is None:
            raise RuntimeError(f"serve {' '.join(args)} did not start: {open(self.log).read()}")

    def cpu_seconds(self):
        fields = open(f"/proc/{self.proc.pid}/stat").read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    def stop(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()


def get(server, target, headers=None, timeout=PROMPT):
    """(status, headers as a dict of lower-case names, body) or (None, {}, error text)."""
    conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=timeout)
    try:
        conn.request("GET", target, headers=headers or {})
        r = conn.getresponse()
        return r.status, {k.lower(): v for k, v in r.getheaders()}, r.read()
    except (OSError, http.client.HTTPException) as e:
        return None, {}, str(e).encode()
    finally:
        conn.close()


def raw(server, data, wait=PROMPT):
    """Sends `data` on a fresh connection; everything read until the server closes or `wait` passes."""
    s = socket.create_connection(("127.0.0.1", server.port), timeout=wait)
    s.sendall(data)
    out, end = b"", time.monotonic() + wait
    try:
        while time.monotonic() < end:
            s.settimeout(max(0.01, end - time.monotonic()))
            chunk = s.recv(65536)
            if not chunk:
                return out, True  # closed by the server
            out += chunk
    except socket.timeout:
        pass
    except OSError:
        return out, True
    finally:
        s.close()
    return out, False


def request(target, extra=""):
    return f"GET {target} HTTP/1.1\r\nHost: 127.0.0.1\r\n{extra}\r\n".encode()


def statuses(data):
    return [int(m) for m in re.findall(rb"HTTP/1\.1 (\d{3}) ", data)]


def all_prompt(server, count, what):
    """`count` requests (/healthz and a cached table, alternately), each answered 200 within PROMPT."""
    slow = []
    for k in range(count):
        start = time.monotonic()
        status, _, _ = get(server, "/healthz" if k % 2 == 0 else CACHED)
        if status not in (200, 503) or (status == 503 and k % 2):  # healthz is 503 only while draining
            slow.append(f"#{k}: {status} after {time.monotonic() - start:.1f} s")
    check(not slow, f"{what}: requests starved: {slow[:3]}")


# --- row 1: slow heads, slow readers, expensive evaluations hold no thread others need ---------
def slowloris(server, count, seconds):
    """`count` connections, each sending a request head one byte per second for `seconds`; returns
    what each received."""
    socks = []
    for _ in range(count):
        s = socket.create_connection(("127.0.0.1", server.port), timeout=5)
        s.sendall(b"GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
        s.setblocking(False)
        socks.append(s)
    received = [b""] * count
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        for k, s in enumerate(socks):
            try:
                s.send(b"a")
            except OSError:
                pass
            try:
                received[k] += s.recv(4096)
            except (BlockingIOError, OSError):
                pass
        time.sleep(1.0)
    for s in socks:
        s.close()
    return received


def probe_slowloris(server):
    box = {}
    t = threading.Thread(target=lambda: box.update(got=slowloris(server, 200, 12.5)))
    t.start()
    time.sleep(1.5)  # all 200 connected and sending
    all_prompt(server, 20, "200 slowloris connections open")
    t.join()
    timed_out = sum(1 for r in box["got"] if statuses(r)[:1] == [408])
    check(timed_out == 200, f"slowloris: {timed_out} of 200 slow heads got 408 within the 10 s header deadline")


def probe_slow_readers(server):
    check(get(server, BIG_JSON, timeout=120)[0] == 200, "the large JSON table")
    readers = []
    for _ in range(16):
        s = socket.socket()
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        s.connect(("127.0.0.1", server.port))
        s.sendall(request(BIG_JSON))
        readers.append(s)
    time.sleep(0.5)
    all_prompt(server, 20, "16 clients that never read a 330 kB answer")
    for s in readers:
        s.close()


def cpu_over(server, seconds):
    before = server.cpu_seconds()
    time.sleep(seconds)
    return server.cpu_seconds() - before


def stops_when_clients_leave(server, clients, what):
    """The CPU the server burns while `clients` wait for their work, then after they close: the
    second must be a small part of the first (relative, so a machine shared with other work
    does not decide it)."""
    running = cpu_over(server, 1.5)
    for s in clients:
        s.close()
    time.sleep(0.5)
    after = cpu_over(server, 1.5)
    check(running > 0.05 and after < max(0.05, 0.25 * running),
          f"{what}: {running:.2f} CPU seconds in 1.5 s while they wait, {after:.2f} after they left")


def probe_expensive_evals(server):
    clients = [socket.create_connection(("127.0.0.1", server.port)) for _ in range(16)]
    for s in clients:
        s.sendall(request(EXPENSIVE_EVAL))
    time.sleep(0.5)
    all_prompt(server, 20, "16 expensive evaluations running")
    stops_when_clients_leave(server, clients, "16 evaluations whose clients left")


# --- row 2: work stops when its client leaves, at its budget, and at SIGTERM --------------------
def probe_client_gone(server):
    s = socket.create_connection(("127.0.0.1", server.port))
    s.sendall(request(EXPENSIVE_EVAL))
    time.sleep(0.5)
    stops_when_clients_leave(server, [s], "an evaluation whose client left")


def probe_budget():
    server = Server("budget", "--max-request-seconds", "2")
    try:
        start = time.monotonic()
        status, _, body = get(server, ENDLESS_BAKE, timeout=20)
        took = time.monotonic() - start
        check(status == 503 and b"s per request" in body and took < 10,
              f"an endless bake under a 2 s budget: {status} after {took:.1f} s: {body[:200]}")
        status, _, body = get(server, EXPENSIVE_EVAL, timeout=20)
        check(status == 503 and b"s per request" in body, f"an endless evaluation under a 2 s budget: {status}")
        health = json.loads(get(server, "/healthz")[2])
        check(health.get("bakes_running") == 0 and health.get("bakes_cancelled") == 1, f"budget: {health}")
        check(not [f for f in os.listdir(server.cache) if not f.endswith(".exr") or f.startswith(".")],
              f"budget: files left: {os.listdir(server.cache)}")
    finally:
        server.stop()


def probe_sigterm():
    server = Server("sigterm")
    try:
        box = {}
        t = threading.Thread(target=lambda: box.update(bake=get(server, ENDLESS_BAKE, timeout=30)))
        t.start()
        for _ in range(100):  # until the bake runs
            status, _, body = get(server, "/healthz")
            if status == 200 and json.loads(body)["bakes_running"] == 1:
                break
            time.sleep(0.05)
        start = time.monotonic()
        server.proc.send_signal(signal.SIGTERM)
        time.sleep(0.2)
        status, _, body = get(server, "/healthz")
        try:
            health = (status, json.loads(body).get("status"))
        except ValueError:
            health = (status, body[:100])
        check(health == (503, "draining"), f"/healthz right after SIGTERM: {health}")
        try:
            code = server.proc.wait(10)
        except subprocess.TimeoutExpired:
            code = None
            server.proc.kill()
            server.proc.wait()
        took = time.monotonic() - start
        print(f"serve_hostile: SIGTERM during an endless bake: exit {code} after {took:.2f} s", flush=True)
        check(code == 0 and took < 5.0, f"SIGTERM during a bake: exit {code} after {took:.1f} s")
        t.join()
        check(box.get("bake", (None,))[0] == 503, f"the bake's request after SIGTERM: {box.get('bake', (None,))[:2]}")
        check(not os.path.exists(server.cache) or not os.listdir(server.cache),
              f"files in the cache after SIGTERM: {os.listdir(server.cache)}")
    finally:
        server.stop()


def probe_lobes(server):
    spec = "%2B".join(["lambert"] * 17)
    status, _, body = get(server, f"/api/eval?model={spec}&law=h&theta_j=10")
    check(status == 413 and b"lobes" in body, f"a mixture of 17 lobes: {status} {body[:200]}")


# --- row 3: Range never yields a partial body under the whole body's ETag ------------------------
def probe_range(server):
    _, h_full, full = get(server, CACHED)
    status, h, body = get(server, CACHED, {"Range": "bytes=0-9"})
    whole = status == 200 and body == full and h.get("etag") == h_full.get("etag")
    partial = status == 206 and len(body) == 10 and h.get("content-range") == f"bytes 0-9/{len(full)}"
    check(whole or partial, f"Range: bytes=0-9 -> {status}, {len(body)} bytes, {h.get('content-range')}")
    check(h.get("accept-ranges") in (None, "none") or partial, f"Accept-Ranges: {h.get('accept-ranges')}")
    status, h, body = get(server, CACHED, {"Range": "bytes=999999-"})
    check((status == 200 and body == full) or (status == 416 and "immutable" not in h.get("cache-control", "")),
          f"Range beyond the body -> {status}, Cache-Control {h.get('cache-control')}")


# --- row 4: a request body is refused, never parsed as the next request --------------------------
def probe_body(server):
    smuggled = request("/api/models")
    data, closed = raw(server, request("/healthz", f"Content-Length: {len(smuggled)}\r\n") + smuggled)
    check(statuses(data) == [413] and closed, f"GET with a Content-Length body: {statuses(data)}, closed {closed}")
    chunk = f"{len(smuggled):x}\r\n".encode() + smuggled + b"\r\n0\r\n\r\n"
    data, closed = raw(server, request("/healthz", "Transfer-Encoding: chunked\r\n") + chunk)
    check(statuses(data) == [413] and closed, f"GET with a chunked body: {statuses(data)}, closed {closed}")
    data, _ = raw(server, b"GET /healthz HTTP/1.1\nHost: 127.0.0.1\nContent-Length: 40\n\n" + smuggled, 1.0)
    check(statuses(data) in ([400], [413]), f"bare-LF head with a body: {statuses(data)}")


# --- row 5: a tampered cache file is baked again, never served ------------------------------------
def probe_tampered(server):
    target = "/api/table?model=minnaert:xi=1.5&law=h&res=64"
    status, h1, body1 = get(server, target, timeout=60)
    name = json.loads(get(server, target + "&format=json")[2])["path"]
    path = os.path.join(server.cache, name)
    nudged = subprocess.run([NUDGE, path, "3"], capture_output=True, text=True)
    check(nudged.returncode == 0, f"exr_nudge: {nudged.stderr}")
    status, h2, body2 = get(server, target, timeout=60)
    check(status == 200 and h2.get("x-ganzfeld-table") == "baked" and h2.get("etag") == h1.get("etag"),
          f"a nudged cache file: {status} {h2.get('x-ganzfeld-table')} ETag {h1.get('etag')} -> {h2.get('etag')}")
    check("refused" in open(server.log).read(), "the refused cache entry is not logged")


# --- rows 6, 7: numbers -----------------------------------------------------------------------
def probe_numbers(server):
    for target, what in [
        ("/api/eval?model=1.7e308*lambert%2B1.7e308*lambert&law=h&theta_j=10", "weights summing past 1.8e308"),
        ("/api/eval?model=lambert&law=h&theta_j=0x1p3", "a hexadecimal float"),
        ("/api/eval?model=lambert&law=g&theta_i=10&theta_j=10&phi=1e308", "phi=1e308"),
    ]:
        status, _, body = get(server, target)
        check(status == 400 and b"nan" not in body, f"{what}: {status} {body[:200]}")


# --- row 7: the smaller ones -----------------------------------------------------------------
def probe_pipelining(server):
    last = request("/healthz?x=1", "Connection: close\r\n")
    data, _ = raw(server, request("/healthz") + request("/api/models") + last)
    got = statuses(data)
    check(got == [200, 200, 400], f"three pipelined requests: {got}")


def probe_304(server):
    _, h, full = get(server, CACHED)
    status, h304, body = get(server, CACHED, {"If-None-Match": h.get("etag", "")})
    length = h304.get("content-length")
    check(status == 304 and body == b"" and length in (None, str(len(full))), f"304: {status}, Content-Length {length}")


def probe_nosniff(server):
    for target in ["/healthz", "/no-such-path", "/api/eval?model=nope&law=h&theta_j=1"]:
        _, h, _ = get(server, target)
        check(h.get("x-content-type-options") == "nosniff", f"{target}: no X-Content-Type-Options: nosniff")


def probe_host(server):
    status, _, body = get(server, "/healthz", {"Host": "evil.example"})
    check(status in (400, 403, 421), f"Host: evil.example -> {status}")
    rebound = {"Host": f"rebound.example:{server.port}"}
    status, _, body = get(server, "/api/table?model=minnaert:xi=7&law=h&res=9", rebound)
    check(status in (400, 403, 421), f"a bake for Host: rebound.example -> {status}")
    check(get(server, "/healthz", {"Host": f"localhost:{server.port}"})[0] == 200, "Host: localhost refused")
    data, _ = raw(server, b"GET /healthz HTTP/1.1\r\n\r\n", 1.0)
    check(statuses(data)[:1] == [400], f"HTTP/1.1 without Host: {statuses(data)}")


def probe_paths(server):
    target = "/api/table?model=minnaert:xi=2.5&law=h&res=9"
    name = json.loads(get(server, target + "&format=json", timeout=60)[2])["path"]
    path = os.path.join(server.cache, name)
    os.remove(path)
    os.makedirs(os.path.join(path, "inside"))
    status, _, body = get(server, target)
    absolute = os.path.realpath(server.cache).encode()
    check(status >= 500 and absolute not in body and server.cache.encode() not in body and TMP.encode() not in body,
          f"a directory at a cache file's name: {status} {body[:300]}")
    os.rmdir(os.path.join(path, "inside"))
    os.rmdir(path)


def probe_if_none_match_star(server):
    before = json.loads(get(server, "/healthz")[2])["tables_baked"]
    target = "/api/table?model=specular:alpha=77&law=g&res=24x24x12"
    status, _, _ = get(server, target, {"If-None-Match": "*"}, timeout=60)
    after = json.loads(get(server, "/healthz")[2])["tables_baked"]
    check(status == 304 and after == before,
          f"If-None-Match: * on a table not baked yet: {status}, {after - before} baked")


def probe_stale_temporaries():
    cache = os.path.join(TMP, "stale-cache")
    os.makedirs(cache)
    stale = os.path.join(cache, ".specular_alpha=8.g.0123456789abcdef.exr.tmp-999999-0")
    fresh = os.path.join(cache, ".specular_alpha=8.g.0123456789abcdef.exr.tmp-999999-1")
    for p in (stale, fresh):
        open(p, "w").write("partial")
    old = time.time() - 7200
    os.utime(stale, (old, old))
    Server("stale", cache=cache).stop()
    check(not os.path.exists(stale) and os.path.exists(fresh),
          f"a kill -9 leftover older than a bake's budget: removed {not os.path.exists(stale)}, "
          f"the fresh one kept {os.path.exists(fresh)}")


def main():
    server = Server("main")
    try:
        check(get(server, CACHED, timeout=60)[0] == 200, "the cached table")
        for probe in (probe_range, probe_body, probe_numbers, probe_pipelining, probe_304, probe_nosniff, probe_host,
                      probe_lobes, probe_if_none_match_star, probe_tampered, probe_paths, probe_slow_readers,
                      probe_slowloris, probe_expensive_evals, probe_client_gone):
            start = time.monotonic()
            before = failed
            try:
                probe(server)
            except Exception as e:  # a probe that breaks counts as failed, the others still run
                check(False, f"{probe.__name__}: {type(e).__name__}: {e}")
            print(f"serve_hostile: {probe.__name__}: {'ok' if failed == before else 'FAILED'} "
                  f"({time.monotonic() - start:.1f} s)", flush=True)
        check(server.proc.poll() is None, "the server died")
    finally:
        server.stop()
    for probe in (probe_budget, probe_sigterm, probe_stale_temporaries):
        before = failed
        try:
            probe()
        except Exception as e:
            check(False, f"{probe.__name__}: {type(e).__name__}: {e}")
        print(f"serve_hostile: {probe.__name__}: {'ok' if failed == before else 'FAILED'}", flush=True)
    print(f"serve_hostile: {passed} passed, {failed} failed")
    subprocess.run(["rm", "-rf", TMP])
    sys.exit(1 if failed else 0)


main()

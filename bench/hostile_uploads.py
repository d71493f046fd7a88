#!/usr/bin/env python3
"""Hostile uploads against a running `clapper serve` (docs/reliability.md):
N clients trickle a byte a second into /api/strikes while M clients send
maximum-size recordings at once; /api/health is asked every second and its
answer time printed, with the server's RSS. Usage:
  python3 bench/hostile_uploads.py PORT PID [N_SLOW] [N_BIG] [SECONDS]"""
import socket, sys, threading, time

port, pid = int(sys.argv[1]), int(sys.argv[2])
n_slow = int(sys.argv[3]) if len(sys.argv) > 3 else 1000
n_big = int(sys.argv[4]) if len(sys.argv) > 4 else 50
seconds = float(sys.argv[5]) if len(sys.argv) > 5 else 30
BIG = 64 << 20
stop = time.time() + seconds
codes = {}
lock = threading.Lock()

def count(k):
    with lock:
        codes[k] = codes.get(k, 0) + 1

def head(length):
    return (f"POST /api/strikes?nominals=400 HTTP/1.1\r\nHost: localhost\r\n"
            f"Content-Length: {length}\r\nConnection: close\r\n\r\n").encode()

def slow():
    try:
        s = socket.create_connection(("127.0.0.1", port), timeout=120)
        s.sendall(head(100000))
        while time.time() < stop:
            s.sendall(b"x")
            time.sleep(1)
        count("slow: still open at the end")
    except Exception as e:
        count("slow: cut off (" + type(e).__name__ + ")")

def big():
    try:
        s = socket.create_connection(("127.0.0.1", port), timeout=120)
        s.sendall(head(BIG))
        chunk = b"\0" * (1 << 20)
        for _ in range(64):
            s.sendall(chunk)
        a = s.recv(64).split(b"\r\n")[0].decode(errors="replace")
        count("big: " + a)
    except Exception as e:
        count("big: " + type(e).__name__)

def rss_mb():
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS"):
            return int(line.split()[1]) / 1024
    return 0.0

threads = [threading.Thread(target=slow, daemon=True) for _ in range(n_slow)]
threads += [threading.Thread(target=big, daemon=True) for _ in range(n_big)]
for t in threads:
    t.start()
worst, peak = 0.0, 0.0
while time.time() < stop:
    t0 = time.time()
    try:
        s = socket.create_connection(("127.0.0.1", port), timeout=30)
        s.sendall(b"GET /api/health HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n")
        ok = s.recv(12).startswith(b"HTTP/1.1 200")
    except Exception:
        ok = False
    dt = time.time() - t0
    worst = max(worst, dt if ok else float("inf"))
    peak = max(peak, rss_mb())
    time.sleep(max(0.0, 1.0 - dt))
for t in threads:
    t.join(timeout=5)
print(f"{n_slow} slow clients, {n_big} big uploads over {seconds:.0f} s")
print(f"health: slowest answer {worst*1000:.0f} ms; server peak RSS {peak:.0f} MB")
for k, v in sorted(codes.items()):
    print(f"  {k}: {v}")

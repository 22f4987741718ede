"""Resident memory per simulated device, bus by bus: `edsgen simulate` serving one device, then
N, each process's VmRSS read once every device says it serves; per device is the difference
over N - 1. CANopen (CP301s on an `edsgen bus` hub), PROFIBUS-DP (Goodrive350 DP cards on a
pseudo-terminal line) and EtherNet/IP (Goodrive350 EtherNet/IP cards, one per loopback address,
all in one process). EtherCAT and PROFINET need root and a veth pair: examples/ethercat_scale.rs
and the PROFINET figures measure those.

Usage: memory_per_device.py EDSGEN [N]      (N defaults to 16; use a release build)
"""

import os
import select
import subprocess
import sys
import time

TIMEOUT = 30.0


def rss_kib(pid):
    with open(f"/proc/{pid}/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS")


def serving(command, ready, count):
    """Starts COMMAND, waits for COUNT stderr lines starting with READY, returns its RSS in KiB."""
    process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE)
    seen, text, end = 0, b"", time.monotonic() + TIMEOUT
    try:
        while seen < count:
            left = end - time.monotonic()
            if left <= 0 or not select.select([process.stderr], [], [], left)[0]:
                raise RuntimeError(f"{command[:3]}: {seen} of {count} devices serve")
            chunk = os.read(process.stderr.fileno(), 65536)
            if not chunk:
                raise RuntimeError(f"{command[:3]} ended: {process.wait()}")
            *lines, text = (text + chunk).split(b"\n")
            seen += sum(line.startswith(ready.encode()) for line in lines)
        time.sleep(0.5)
        return rss_kib(process.pid)
    finally:
        process.terminate()
        process.wait(timeout=10)


def canopen(edsgen, n):
    hub = subprocess.Popen([edsgen, "bus", "--listen", "127.0.0.1:29599"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(0.5)
    try:
        cards = [a for node in range(2, 2 + n) for a in ("--card", f"cp301@{node}")]
        return serving([edsgen, "simulate", "--bus", "127.0.0.1:29599", *cards],
                       "simulating node", n)
    finally:
        hub.terminate()
        hub.wait(timeout=10)


def profibus(edsgen, n):
    pair = subprocess.Popen([sys.executable, os.path.join(os.path.dirname(__file__), "pty_pair.py")],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        line = pair.stdout.readline().split()
        tty = line[2]
        cards = [a for station in range(2, 2 + n) for a in ("--card", f"goodrive350-dp@{station}")]
        return serving([edsgen, "simulate", "--profibus", tty, *cards], "simulating DP slave", n)
    finally:
        pair.stdin.close()
        pair.wait(timeout=10)


def enip(edsgen, n):
    addresses = ",".join(f"127.0.0.{2 + k}" for k in range(n))
    return serving([edsgen, "simulate", "--enip", addresses, "--card", "goodrive350-enip"],
                   "serving ", n)


def main():
    edsgen = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 16
    print(f"resident memory, 1 and {n} simulated devices in one `edsgen simulate`:")
    for name, measure in (("CANopen (CP301)", canopen), ("PROFIBUS-DP (Goodrive350 DP)", profibus),
                          ("EtherNet/IP (Goodrive350 EtherNet/IP)", enip)):
        one, many = measure(edsgen, 1), measure(edsgen, n)
        per = (many - one) / (n - 1)
        print(f"  {name}: {one} KiB with 1, {many} KiB with {n}: {per:.0f} KiB per device")


if __name__ == "__main__":
    main()

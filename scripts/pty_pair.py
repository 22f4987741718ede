"""Two pseudo-terminals joined by a relay, as `socat pty,raw,echo=0 pty,raw,echo=0` would make:
prints `PTY <a> <b>` and relays bytes between them until stdin closes."""

import os
import select
import sys
import threading
import tty


def relay(a, b):
    while True:
        ready, _, _ = select.select([a, b], [], [])
        for fd in ready:
            try:
                data = os.read(fd, 4096)
            except OSError:
                return
            if not data:
                return
            os.write(b if fd == a else a, data)


master_a, slave_a = os.openpty()
master_b, slave_b = os.openpty()
tty.setraw(slave_a)
tty.setraw(slave_b)
threading.Thread(target=relay, args=(master_a, master_b), daemon=True).start()
print("PTY", os.ttyname(slave_a), os.ttyname(slave_b), flush=True)
sys.stdin.read()

"""A class-1 EtherNet/IP scanner for the Goodrive350 card, on PyPI `ethernetip` 1.2.0 (pinned in
scripts/python-venv.sh), driven by tests/enip_ethernetip.rs in a network namespace of its own.

    python enip_scanner.py ADAPTER_IP

Opens 150 -> 100 at 50 ms, sets P16.32 and P16.43 to 1 through PKW (task 4), reads P00.10, is
refused a write of P07.27 (read only), runs forward at 25.00 Hz through PZD2, watches SW and the
transmitted PZD2, closes the connection; then opens a second connection and stops producing
without closing it. Prints one JSON object per step on stdout; the test judges them.
"""

import json
import sys
import time

from ethernetip import ethernetip as enip

IP = sys.argv[1]


def put_word(bits, index, value):
    for bit in range(16):
        bits[16 * index + bit] = bool((value >> bit) & 1)


def get_word(bits, index):
    return sum(1 << bit for bit in range(16) if bits[16 * index + bit])


def words(bits):
    return [get_word(bits, i) for i in range(16)]


def report(step, **values):
    print(json.dumps(dict(step=step, **values)), flush=True)


def pkw(out, inp, task, address, value, cw):
    """One PKW request; the response words once PKW2 echoes the address (or after 2 s)."""
    put_word(out, 0, task)
    put_word(out, 1, address)
    put_word(out, 2, 0)
    put_word(out, 3, value)
    put_word(out, 4, cw)
    deadline = time.time() + 2.0
    while time.time() < deadline:
        time.sleep(0.1)
        w = words(inp)
        if w[1] == address and w[0] != 0:
            break
    w = words(inp)
    put_word(out, 0, 0)
    put_word(out, 1, 0)
    put_word(out, 3, 0)
    time.sleep(0.2)
    return w


scanner = enip.EtherNetIP(IP)
conn = scanner.explicit_conn(IP)
if conn.registerSession() is None:
    report("register", ok=False)
    sys.exit(1)
inp = scanner.registerAssembly(enip.EtherNetIP.ENIP_IO_TYPE_INPUT, 32, 100, conn)
out = scanner.registerAssembly(enip.EtherNetIP.ENIP_IO_TYPE_OUTPUT, 32, 150, conn)
scanner.startIO()
status = conn.sendFwdOpenReq(100, 150, 1, torpi=50, otrpi=50)
report("forward_open", status=status)
conn.produce()
time.sleep(0.5)
report("idle", words=words(inp))

WRITE = 0x0100  # CW bit 8: enable writing through PKW
report("p16_32", words=pkw(out, inp, 4, 0x1020, 1, WRITE))
report("p16_43", words=pkw(out, inp, 4, 0x102B, 1, WRITE))
report("p00_10", words=pkw(out, inp, 1, 0x000A, 0, 0))
report("read_only", words=pkw(out, inp, 4, 0x071B, 1, WRITE))

put_word(out, 5, 2500)  # PZD2: 25.00 Hz
put_word(out, 4, 0x0001)  # CW: run forward (Table 5-5)
time.sleep(0.6)
first = words(inp)
time.sleep(1.0)
later = words(inp)
report("running", first=first, later=later)

put_word(out, 4, 0x0005)  # decelerate to stop
time.sleep(0.3)
conn.stopProduce()
report("forward_close", status=conn.sendFwdCloseReq(100, 150, 1))

# A connection that stops producing: the adapter times it out (4 x 50 ms), the drive trips.
status = conn.sendFwdOpenReq(100, 150, 1, torpi=50, otrpi=50)
conn.produce()
time.sleep(0.5)
conn.stopProduce()
time.sleep(1.0)
report("stopped_producing", status=status)
scanner.stopIO()

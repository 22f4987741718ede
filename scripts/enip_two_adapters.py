"""Class-1 connections to two EtherNet/IP adapters at once, on PyPI `ethernetip` 1.2.0 (pinned in
scripts/python-venv.sh), driven by tests/enip_two_adapters.rs from a network namespace of its own.

    python enip_two_adapters.py IP_A IP_B

One scanner (one UDP 2222 socket) opens 150 -> 100 at 50 ms to the Goodrive350 card on each
address, then sends each its own PKW read (P00.10 to A, P00.11 to B) and reports, for each
adapter, the output bytes it produced and the input bytes it consumed once the response came.
"""

import json
import sys
import time

from ethernetip import ethernetip as enip

ADDRESSES = sys.argv[1:3]
READS = {ADDRESSES[0]: 0x000A, ADDRESSES[1]: 0x000B}


def put_word(bits, index, value):
    for bit in range(16):
        bits[16 * index + bit] = bool((value >> bit) & 1)


def as_bytes(bits):
    return [sum(1 << b for b in range(8) if bits[8 * n + b]) for n in range(len(bits) // 8)]


scanner = enip.EtherNetIP(ADDRESSES[0])
links = {}
for address in ADDRESSES:
    conn = scanner.explicit_conn(address)
    if conn.registerSession() is None:
        print(json.dumps(dict(address=address, registered=False)), flush=True)
        sys.exit(1)
    inp = scanner.registerAssembly(enip.EtherNetIP.ENIP_IO_TYPE_INPUT, 32, 100, conn)
    out = scanner.registerAssembly(enip.EtherNetIP.ENIP_IO_TYPE_OUTPUT, 32, 150, conn)
    links[address] = (conn, inp, out)
scanner.startIO()
for address, (conn, inp, out) in links.items():
    status = conn.sendFwdOpenReq(100, 150, 1, torpi=50, otrpi=50)
    print(json.dumps(dict(address=address, forward_open=status)), flush=True)
    put_word(out, 0, 1)  # PKW1: task 1, read
    put_word(out, 1, READS[address])  # PKW2: the parameter
    conn.produce()
deadline = time.time() + 5.0
answered = {}
while time.time() < deadline and len(answered) < len(links):
    time.sleep(0.1)
    for address, (conn, inp, out) in links.items():
        got = as_bytes(inp)
        if got[0] == 1 and got[2] == READS[address]:
            answered[address] = got
time.sleep(0.2)
for address, (conn, inp, out) in links.items():
    conn.stopProduce()
    closed = conn.sendFwdCloseReq(100, 150, 1)
    line = dict(address=address, output=as_bytes(out), input=as_bytes(inp), forward_close=closed)
    print(json.dumps(line), flush=True)
scanner.stopIO()

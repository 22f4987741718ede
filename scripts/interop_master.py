"""python canopen 2.4.1 as the master of an edsgen device through a socketcand hub.

Used by tests/interop_python.rs, which runs the hub and the device and asserts the values this
script reports. Usage:

    interop_master.py full PORT EDS NODE_ID      every service, on a CP301 card
    interop_master.py loop PORT EDS NODE_ID N    N expedited write/read pairs of 6042h
    interop_master.py strings PORT EDS NODE_ID   1008h-100Ah uploaded segmented and in blocks
    interop_master.py large PORT EDS NODE_ID DIR  a domain (2001h) by block transfer both ways and
                                                  a string (2000h) segmented both ways; the values
                                                  are files in DIR (see `large`)
    interop_master.py chunked PORT EDS NODE_ID DIR  DIR/domain-down.bin to 2001h by block download
                                                  written in 127-byte pieces to a stream buffered
                                                  by 127 bytes (python canopen's issue #379)

It prints `WAIT <what>` when the test must act on the device (boot it, raise an error) and reads
one line from stdin when it has; at the end it prints `RESULT <json>`. Any failure is a python
exception: a traceback on stderr and exit code 1.
"""

import json
import os
import statistics
import struct
import sys
import threading
import time

import canopen
from canopen.sdo.exceptions import SdoAbortedError, SdoCommunicationError

TIMEOUT = 5.0


def wait_until(predicate, what, timeout=TIMEOUT):
    end = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > end:
            raise TimeoutError(f"no {what} within {timeout} s")
        time.sleep(0.002)


def ask_test(what):
    """Lets the test act on the device, and waits until it has."""
    print(f"WAIT {what}", flush=True)
    if sys.stdin.readline().strip() != "GO":
        raise RuntimeError(f"the test did not answer WAIT {what}")


class Recorder:
    """Every frame on one COB-ID, with the time it arrived."""

    def __init__(self, network, cob_id):
        self.frames = []
        self.lock = threading.Lock()
        network.subscribe(cob_id, self.on_message)

    def on_message(self, can_id, data, timestamp):
        with self.lock:
            self.frames.append((time.monotonic(), bytes(data)))

    def count(self):
        with self.lock:
            return len(self.frames)

    def since(self, start):
        with self.lock:
            return [frame for frame in self.frames[start:]]

    def next_from(self, start, what, predicate=lambda data: True):
        """The data of the first frame at or after position `start` that satisfies `predicate`."""
        found = []

        def seen():
            found[:] = [d for _, d in self.since(start) if predicate(d)]
            return bool(found)

        wait_until(seen, what)
        return found[0]


def abort_code(action):
    try:
        action()
    except SdoAbortedError as error:
        return f"{error.code:08X}"
    return "no abort"


def full(network, node, results):
    heartbeat = Recorder(network, 0x700 + node.id)
    ask_test("bootup")
    results["boot-up"] = heartbeat.next_from(0, "boot-up").hex()

    # SDO expedited, both ways.
    results["expedited upload 1000"] = node.sdo.upload(0x1000, 0).hex()
    node.sdo[0x6042].raw = -1500
    results["expedited 6042 written and read"] = node.sdo[0x6042].raw

    # Segmented download (forced, the entry is 2 bytes) and block transfers both ways.
    node.sdo.download(0x6040, 0, struct.pack("<H", 0x1234), force_segment=True)
    results["segmented download 6040, read back"] = node.sdo.upload(0x6040, 0).hex()
    with node.sdo.open(0x6042, 0, "wb", block_transfer=True, size=2) as stream:
        stream.write(struct.pack("<h", 777))
    results["block download 6042, read back"] = node.sdo[0x6042].raw
    with node.sdo.open(0x6040, 0, "rb", block_transfer=True) as stream:
        results["block upload 6040"] = stream.read().hex()

    # Abort codes.
    results["abort: upload 5FFF:00"] = abort_code(lambda: node.sdo.upload(0x5FFF, 0))
    results["abort: upload 1018:09"] = abort_code(lambda: node.sdo.upload(0x1018, 9))
    results["abort: download 1000:00 (ro)"] = abort_code(
        lambda: node.sdo.download(0x1000, 0, b"\x01\x00\x00\x00"))
    results["abort: download 3 bytes to 6040:00"] = abort_code(
        lambda: node.sdo.download(0x6040, 0, b"\x01\x02\x03"))
    results["abort: download 1 byte to 6040:00"] = abort_code(
        lambda: node.sdo.download(0x6040, 0, b"\x01"))

    # Heartbeat and NMT.
    node.sdo[0x1017].raw = 50
    start = heartbeat.count()
    time.sleep(0.6)
    beats = heartbeat.since(start)
    results["heartbeats in pre-operational"] = sorted({d.hex() for _, d in beats})
    gaps = [b[0] - a[0] for a, b in zip(beats, beats[1:])]
    results["heartbeat period ms"] = round(statistics.median(gaps) * 1000)
    for state, wanted in [("OPERATIONAL", 0x05), ("STOPPED", 0x04), ("PRE-OPERATIONAL", 0x7F)]:
        start = heartbeat.count()
        node.nmt.state = state
        heartbeat.next_from(start, f"heartbeat {wanted:02X}", lambda d, w=wanted: d == bytes([w]))
        results[f"nmt {state}: python's state"] = node.nmt.state

    # PDOs, configured through python's PDO API; exchanged on SYNC.
    node.tpdo.read()
    node.rpdo.read()
    tpdo = node.tpdo[1]
    tpdo.clear()
    tpdo.add_variable(0x6040)
    tpdo.add_variable(0x6042)
    tpdo.trans_type = 1
    tpdo.enabled = True
    rpdo = node.rpdo[1]
    rpdo.clear()
    rpdo.add_variable(0x6040)
    rpdo.add_variable(0x6042)
    rpdo.trans_type = 255
    rpdo.enabled = True
    node.tpdo.save()
    node.rpdo.save()
    results["tpdo1 as the device has it"] = [
        f"{node.sdo[0x1800][1].raw:08X}", node.sdo[0x1800][2].raw,
        node.sdo[0x1A00][0].raw, f"{node.sdo[0x1A00][1].raw:08X}", f"{node.sdo[0x1A00][2].raw:08X}"]
    results["rpdo1 as the device has it"] = [
        f"{node.sdo[0x1400][1].raw:08X}", node.sdo[0x1400][2].raw,
        node.sdo[0x1600][0].raw, f"{node.sdo[0x1600][1].raw:08X}", f"{node.sdo[0x1600][2].raw:08X}"]
    received = []
    tpdo.add_callback(lambda pdo: received.append({f"{v.index:04X}": v.raw for v in pdo}))
    tpdo_frames = Recorder(network, tpdo.cob_id)
    node.nmt.state = "OPERATIONAL"
    rpdo["Controlword"].raw = 0x000F
    rpdo["vl target velocity"].raw = -300
    rpdo.transmit()
    for _ in range(3):
        count = len(received)
        network.sync.transmit()
        wait_until(lambda: len(received) > count, "TPDO after SYNC")
    results["tpdo1 on three syncs"] = received
    results["tpdo1 frame"] = tpdo_frames.since(0)[0][1].hex()

    # EMCY: an RPDO too short for its mapping, then a good one; then one the device raises.
    network.send_message(rpdo.cob_id, b"\x0f")
    wait_until(lambda: len(node.emcy.log) >= 1, "EMCY")
    short = node.emcy.log[-1]
    results["emcy: short rpdo"] = [f"{short.code:04X}", f"{short.register:02X}", short.data.hex()]
    results["1001 after the short rpdo"] = f"{node.sdo[0x1001].raw:02X}"
    network.send_message(rpdo.cob_id, b"\x0f\x00\xd4\xfe")
    wait_until(lambda: len(node.emcy.log) >= 2, "error-reset EMCY")
    reset = node.emcy.log[-1]
    results["emcy: error reset"] = [f"{reset.code:04X}", f"{reset.register:02X}", reset.data.hex()]
    ask_test("emcy")
    wait_until(lambda: len(node.emcy.log) >= 3, "EMCY raised by the device")
    raised = node.emcy.log[-1]
    results["emcy: raised by the device"] = [
        f"{raised.code:04X}", f"{raised.register:02X}", raised.data.hex()]

    # Reset communication: a new boot-up.
    start = heartbeat.count()
    node.nmt.state = "RESET COMMUNICATION"
    results["boot-up after reset communication"] = heartbeat.next_from(
        start, "boot-up", lambda d: d == b"\x00").hex()


def loop(node, count, results):
    mismatches = 0
    for i in range(count):
        value = (i * 7919) % 65536 - 32768
        node.sdo[0x6042].raw = value
        if node.sdo[0x6042].raw != value:
            mismatches += 1
    results["round trips"] = count
    results["mismatches"] = mismatches


def strings(node, results):
    for index in (0x1008, 0x1009, 0x100A):
        results[f"segmented upload {index:04X}"] = node.sdo.upload(index, 0).decode("ascii")
        with node.sdo.open(index, 0, "rb", block_transfer=True) as stream:
            results[f"block upload {index:04X}"] = stream.read().decode("ascii")


def large(node, directory, results):
    """Downloads DIR/domain-down.bin to 2001h by block transfer and DIR/string-down.bin to 2000h
    segmented, and reads each back the same way (DIR/domain-read-back.bin,
    DIR/string-read-back.bin); then, once the test has put other values in the device, uploads
    them again (DIR/domain-up.bin, DIR/string-up.bin)."""
    def load(name):
        with open(os.path.join(directory, name), "rb") as f:
            return f.read()

    def store(name, data):
        with open(os.path.join(directory, name), "wb") as f:
            f.write(data)

    def block_upload():
        with node.sdo.open(0x2001, 0, "rb", block_transfer=True) as stream:
            return stream.read()

    domain = load("domain-down.bin")
    with node.sdo.open(0x2001, 0, "wb", size=len(domain), block_transfer=True) as stream:
        stream.write(domain)
    store("domain-read-back.bin", block_upload())
    text = load("string-down.bin")
    node.sdo.download(0x2000, 0, text)
    store("string-read-back.bin", node.sdo.upload(0x2000, 0))
    ask_test("downloaded")
    store("domain-up.bin", block_upload())
    store("string-up.bin", node.sdo.upload(0x2000, 0))
    results["done"] = True


def chunked(node, directory, results):
    """A block download written piece by piece, as canopen's documentation and issue #379 do:
    reports what `write` and `close` raise."""
    with open(os.path.join(directory, "domain-down.bin"), "rb") as f:
        data = f.read()
    stream = node.sdo.open(0x2001, 0, "wb", size=len(data), block_transfer=True, buffering=127)
    written = 0
    try:
        for start in range(0, len(data), 127):
            stream.write(data[start:start + 127])
            written += len(data[start:start + 127])
        results["write"] = "no error"
    except BlockingIOError as error:
        results["write"] = f"{type(error).__name__} after {written} bytes: {error.strerror}"
    try:
        stream.close()
        results["close"] = "no error"
    except SdoCommunicationError as error:
        results["close"] = f"{type(error).__name__}: {error}"


def main():
    mode, port, eds, node_id = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
    network = canopen.Network()
    network.connect(interface="socketcand", channel="can0", host="127.0.0.1", port=port,
                    tcp_tune=True)
    results = {}
    try:
        node = canopen.RemoteNode(node_id, eds)
        network.add_node(node)
        node.sdo.RESPONSE_TIMEOUT = 2.0
        if mode == "full":
            full(network, node, results)
        elif mode == "loop":
            loop(node, int(sys.argv[5]), results)
        elif mode == "strings":
            strings(node, results)
        elif mode == "large":
            large(node, sys.argv[5], results)
        elif mode == "chunked":
            chunked(node, sys.argv[5], results)
        else:
            raise SystemExit(f"unknown mode {mode}")
    finally:
        network.disconnect()
    print("RESULT " + json.dumps(results), flush=True)


if __name__ == "__main__":
    main()

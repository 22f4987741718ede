"""SOEM (python pysoem, pinned in scripts/python-venv.sh) as the MainDevice of an EtherCAT
segment on IFACE (tests/ethercat_segment.rs): discovery, each SubDevice's identity, name and image
sizes, Op with the working counter it expects, then the EC-TX508s among them driven in cyclic
synchronous velocity, each to its own speed (300 rpm for the first, 150 for the second). Prints
one line per finding; exits 1 if Op or a speed is not reached.

    python scripts/soem_segment.py IFACE
"""
import struct
import sys
import time

import pysoem

EC_TX508 = (0x04D8, 0x9252)
SPEEDS = (300, 150)


def command(status, target):
    """The CiA 402 controlword (and the speed to ask) that moves a drive towards
    Operation enabled from its statusword."""
    if status & 0x0008:
        return 0x0080, 0
    state = status & 0x006F
    if state == 0x0027:
        return 0x000F, target
    if state == 0x0023:
        return 0x000F, 0
    if state == 0x0021:
        return 0x0007, 0
    return 0x0006, 0


def main():
    iface = sys.argv[1]
    master = pysoem.Master()
    master.open(iface)
    try:
        found = master.config_init()
        print("found", found, flush=True)
        if found < 1:
            return 1
        master.config_map()
        if master.state_check(pysoem.SAFEOP_STATE, 2_000_000) != pysoem.SAFEOP_STATE:
            print("safe-op not reached", flush=True)
            return 1
        for n, slave in enumerate(master.slaves):
            print("%d identity %#010x %#010x %#010x name %s images %d/%d" % (
                n, slave.man, slave.id, slave.rev, slave.name, len(slave.output),
                len(slave.input)), flush=True)
        expected = master.expected_wkc
        master.state = pysoem.OP_STATE
        master.send_processdata()
        master.receive_processdata(100_000)
        master.write_state()
        state = 0
        for _ in range(200):
            master.send_processdata()
            master.receive_processdata(100_000)
            state = master.state_check(pysoem.OP_STATE, 50_000)
            if state == pysoem.OP_STATE:
                break
        print("op", state == pysoem.OP_STATE, flush=True)
        wkcs = []
        for _ in range(20):
            master.send_processdata()
            wkcs.append(master.receive_processdata(100_000))
        print("wkc %d expected %d" % (min(wkcs), expected), flush=True)
        drives = [s for s in master.slaves if (s.man, s.id) == EC_TX508]
        speeds = [0] * len(drives)
        for _ in range(3000):
            for k, drive in enumerate(drives):
                status, speed = struct.unpack_from("<H4xi", drive.input, 0)
                speeds[k] = speed
                controlword, target = command(status, SPEEDS[k % len(SPEEDS)])
                outputs = bytearray(len(drive.output))
                struct.pack_into("<HiiHHb", outputs, 0, controlword, 0, target, 0, 0, 9)
                drive.output = bytes(outputs)
            if tuple(speeds) == SPEEDS[:len(drives)]:
                break
            master.send_processdata()
            master.receive_processdata(100_000)
            time.sleep(0.001)
        print("speeds", " ".join(str(s) for s in speeds), flush=True)
        master.state = pysoem.INIT_STATE
        master.write_state()
        print("done", flush=True)
        reached = tuple(speeds) == SPEEDS[:len(drives)]
        return 0 if state == pysoem.OP_STATE and reached else 1
    finally:
        master.close()


if __name__ == "__main__":
    sys.exit(main())

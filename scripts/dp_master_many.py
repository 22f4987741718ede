"""pyprofibus (PyPI, pinned in scripts/python-venv.sh) as the DP master of several simulated
slaves on one serial line: `python scripts/dp_master_many.py GSD ADDRESS:KIND...` (KIND `card`
for the Goodrive350 card, `echo` for a slave simulated from a GSD file alone).

Makes the pseudo-terminal pair and relay of `dp_master.py`, prints `PTY <path>` for the slaves'
side, configures pyprofibus's DPM1 with one slave per ADDRESS from GSD and exchanges data with
all of them: a card is asked for P00.10 through PKW (`OK <address> 0001000a00001388`), an echo
slave must return its outputs (`OK <address> <the first 4 bytes>`), printed in the order the
addresses were given once every slave got there. Exit 0 then, 1 on a timeout (30 s) with the
addresses that were missing.
"""

import os
import sys
import tempfile
import threading
import time
import tty

import pyprofibus

from dp_master import relay


def main():
    gsd = sys.argv[1]
    slaves = [(int(a), kind) for a, kind in (arg.split(":") for arg in sys.argv[2:])]
    master_a, slave_a = os.openpty()
    master_b, slave_b = os.openpty()
    tty.setraw(slave_a)
    tty.setraw(slave_b)
    threading.Thread(target=relay, args=(master_a, master_b), daemon=True).start()
    print("PTY", os.ttyname(slave_b), flush=True)
    conf = "[PROFIBUS]\ndebug = 0\n[PHY]\ntype = serial\ndev = %s\nbaud = 19200\n" % os.ttyname(slave_a)
    conf += "rtscts = False\ndsrdtr = False\n[DP]\nmaster_class = 1\nmaster_addr = 1\n"
    for n, (address, _) in enumerate(slaves):
        conf += (
            "[SLAVE_%d]\nname = s%d\naddr = %d\ngsd = %s\nsync_mode = 0\nfreeze_mode = 0\n"
            "group_mask = 1\nwatchdog_ms = 500\ninput_size = 32\noutput_size = 32\n"
            % (n, address, address, gsd)
        )
    path = os.path.join(tempfile.mkdtemp(), "dp.conf")
    with open(path, "w") as f:
        f.write(conf)
    conf = pyprofibus.PbConf.fromFile(path)
    master = conf.makeDPM()
    descs = {}
    for slave_conf in conf.slaveConfs:
        desc = slave_conf.makeDpSlaveDesc()
        master.addSlave(desc)
        descs[slave_conf.addr] = desc
    master.initialize()
    outputs = {}
    for address, kind in slaves:
        if kind == "card":
            out = bytearray(32)
            out[0:4] = bytes([0, 1, 0, 10])
        else:
            out = bytearray([address, 0xA5, 0x5A, address]) + bytearray(28)
        outputs[address] = bytes(out)
    done = {}
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and len(done) < len(slaves):
        for address, desc in descs.items():
            desc.setMasterOutData(outputs[address])
        desc = master.run()
        if desc is None:
            continue
        inputs = desc.getMasterInData()
        if inputs is None:
            continue
        address = desc.slaveAddr
        kind = dict(slaves)[address]
        inputs = bytes(inputs)
        if kind == "card" and inputs[:8] == bytes.fromhex("0001000a00001388"):
            done[address] = inputs[:8].hex()
        elif kind == "echo" and inputs == outputs[address]:
            done[address] = inputs[:4].hex()
    for address, _ in slaves:
        if address in done:
            print("OK", address, done[address], flush=True)
    missing = [a for a, _ in slaves if a not in done]
    if missing:
        print("TIMEOUT waiting for", *missing, flush=True)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""pyprofibus (PyPI, pinned in scripts/python-venv.sh) as the DP master of a simulated slave on a
serial line: `python scripts/dp_master.py GSD ADDRESS [echo]`.

Makes two pseudo-terminal pairs joined by a relay (as `socat pty,raw pty,raw` would), prints
`PTY <path>` for the slave's side on stdout, runs pyprofibus's DPM1 with its serial PHY on the
other side, configured from GSD (its Ident_Number and module), and drives the Goodrive350's
PKW/PZD protocol through data exchange, printing one line per step reached:

    DATA_EXCHANGE
    PKW_READ <the first 8 input bytes in hex>     (task 1, address 10: P00.10)
    RUN <SW and PZD2 in hex>                      (CW 1, PZD2 = 10.00 Hz)

With `echo` (a slave simulated from a GSD file alone, whose inputs echo its outputs) each step
is reached when the inputs equal the outputs.

Exit 0 when every step was reached, 1 on a timeout (20 s) with the step that was missing.
"""

import os
import select
import sys
import tempfile
import threading
import time
import tty

import pyprofibus


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


def main(before_master=None):
    """Runs the master; `before_master(fd, address)`, if given, gets the slave's line (the
    relay's end of it) first, before the relay and the master start."""
    gsd, address = sys.argv[1], int(sys.argv[2])
    echo = sys.argv[3:] == ["echo"]
    master_a, slave_a = os.openpty()
    master_b, slave_b = os.openpty()
    tty.setraw(slave_a)
    tty.setraw(slave_b)
    print("PTY", os.ttyname(slave_b), flush=True)
    if before_master is not None:
        before_master(master_b, address)
    threading.Thread(target=relay, args=(master_a, master_b), daemon=True).start()

    conf_dir = tempfile.mkdtemp()
    conf_path = os.path.join(conf_dir, "dp.conf")
    with open(conf_path, "w") as f:
        f.write(
            "[PROFIBUS]\ndebug = 0\n"
            "[PHY]\ntype = serial\ndev = %s\nbaud = 19200\nrtscts = False\ndsrdtr = False\n"
            "[DP]\nmaster_class = 1\nmaster_addr = 1\n"
            "[SLAVE_0]\nname = gd350\naddr = %d\ngsd = %s\nsync_mode = 0\nfreeze_mode = 0\n"
            "group_mask = 1\nwatchdog_ms = 500\ninput_size = 32\noutput_size = 32\n"
            % (os.ttyname(slave_a), address, gsd)
        )
    conf = pyprofibus.PbConf.fromFile(conf_path)
    master = conf.makeDPM()
    slave = conf.slaveConfs[0].makeDpSlaveDesc()
    master.addSlave(slave)
    master.initialize()

    def words(pkw, cw, pzd2):
        out = bytearray(32)
        for n, word in enumerate(list(pkw) + [cw, pzd2]):
            out[2 * n : 2 * n + 2] = word.to_bytes(2, "big")
        return bytes(out)

    steps = [
        ("PKW_READ", words([1, 10, 0, 0], 0, 0), lambda i: i[:8] == bytes.fromhex("0001000a00001388"), 0, 8),
        ("RUN", words([0, 0, 0, 0], 1, 1000), lambda i: i[8:12] == bytes.fromhex("410103e8"), 8, 12),
    ]
    connected = False
    deadline = time.monotonic() + 20
    step = 0
    while time.monotonic() < deadline:
        # pyprofibus sends Data_Exchange only for outputs given since the last one.
        slave.setMasterOutData(steps[step][1])
        desc = master.run()
        if desc is None:
            continue
        inputs = desc.getMasterInData()
        if not connected and slave.isConnected():
            connected = True
            print("DATA_EXCHANGE", flush=True)
        if inputs is None:
            continue
        name, _, done, lo, hi = steps[step]
        if (bytes(inputs) == steps[step][1]) if echo else done(bytes(inputs)):
            print(name, bytes(inputs[lo:hi]).hex(), flush=True)
            step += 1
            if step == len(steps):
                return 0
    print("TIMEOUT waiting for", "DATA_EXCHANGE" if not connected else steps[step][0], flush=True)
    return 1


if __name__ == "__main__":
    sys.exit(main())

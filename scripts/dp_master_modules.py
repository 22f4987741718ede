"""pyprofibus (PyPI, pinned in scripts/python-venv.sh) as the DP master of a simulated modular
slave: `python scripts/dp_master_modules.py GSD ADDRESS INPUT_SIZE OUTPUT_SIZE MODULE...`
(the master's inputs and outputs: the bytes the slave answers and the bytes it is sent).

As scripts/dp_master.py (a relay between two pseudo-terminal pairs, `PTY <path>` printed for the
slave's side), but pyprofibus plugs the MODULEs (`module_0`, `module_1`, ... of its slave
configuration, names as the GSD writes them) and sends their Chk_Cfg bytes. It prints
`DATA_EXCHANGE` once the slave is connected, then sets the outputs to 1, 2, 3, ... and prints
`ECHO <the inputs in hex>` when the slave's inputs echo them (a slave simulated from a GSD file
echoes its outputs).

Exit 0 when both steps were reached, 1 on a timeout (20 s).
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
    gsd, address = sys.argv[1], int(sys.argv[2])
    input_size, output_size = int(sys.argv[3]), int(sys.argv[4])
    modules = sys.argv[5:]
    master_a, slave_a = os.openpty()
    master_b, slave_b = os.openpty()
    tty.setraw(slave_a)
    tty.setraw(slave_b)
    print("PTY", os.ttyname(slave_b), flush=True)
    threading.Thread(target=relay, args=(master_a, master_b), daemon=True).start()

    conf_dir = tempfile.mkdtemp()
    conf_path = os.path.join(conf_dir, "dp.conf")
    plugged = "".join("module_%d = %s\n" % (n, m) for n, m in enumerate(modules))
    with open(conf_path, "w") as f:
        f.write(
            "[PROFIBUS]\ndebug = 0\n"
            "[PHY]\ntype = serial\ndev = %s\nbaud = 19200\nrtscts = False\ndsrdtr = False\n"
            "[DP]\nmaster_class = 1\nmaster_addr = 1\n"
            "[SLAVE_0]\nname = modular\naddr = %d\ngsd = %s\nsync_mode = 0\nfreeze_mode = 0\n"
            "group_mask = 1\nwatchdog_ms = 500\ninput_size = %d\noutput_size = %d\n%s"
            # pyprofibus names the sizes as the slave sees them: its input is our output.
            % (os.ttyname(slave_a), address, gsd, output_size, input_size, plugged)
        )
    conf = pyprofibus.PbConf.fromFile(conf_path)
    master = conf.makeDPM()
    slave = conf.slaveConfs[0].makeDpSlaveDesc()
    master.addSlave(slave)
    master.initialize()

    outputs = bytes(range(1, output_size + 1))
    echo = (outputs + bytes(input_size))[:input_size]
    connected = False
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        # pyprofibus sends Data_Exchange only for outputs given since the last one.
        slave.setMasterOutData(outputs)
        desc = master.run()
        if desc is None:
            continue
        inputs = desc.getMasterInData()
        if not connected and slave.isConnected():
            connected = True
            print("DATA_EXCHANGE", flush=True)
        if inputs is not None and bytes(inputs) == echo:
            print("ECHO", bytes(inputs).hex(), flush=True)
            return 0
    print("TIMEOUT waiting for", "DATA_EXCHANGE" if not connected else "ECHO", flush=True)
    return 1


if __name__ == "__main__":
    sys.exit(main())

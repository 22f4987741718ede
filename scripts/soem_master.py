"""SOEM (python pysoem, pinned in scripts/python-venv.sh) as the MainDevice of one EtherCAT
SubDevice on IFACE: discovery, the identity and name it reads from the SII, mapping, Safe-Op and
Op, then a few cycles. Prints one `key value` line per finding; exits 1 if Op is not reached.

    python scripts/soem_master.py IFACE
"""
import sys

import pysoem


def main():
    iface = sys.argv[1]
    master = pysoem.Master()
    master.open(iface)
    try:
        found = master.config_init()
        print("found", found, flush=True)
        if found != 1:
            return 1
        slave = master.slaves[0]
        print("identity %#010x %#010x %#010x" % (slave.man, slave.id, slave.rev), flush=True)
        print("name", slave.name, flush=True)
        size = master.config_map()
        print("iomap", size, flush=True)
        print("state", master.state_check(pysoem.SAFEOP_STATE, 2_000_000), flush=True)
        print("images %d/%d" % (len(slave.output), len(slave.input)), flush=True)
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
        master.state = pysoem.INIT_STATE
        master.write_state()
        return 0 if state == pysoem.OP_STATE else 1
    finally:
        master.close()


if __name__ == "__main__":
    sys.exit(main())

"""python canopen 2.4.1 LocalNode as a device for the edsgen master, through a socketcand hub.

Used by tests/interop_python_master.rs. Usage:

    interop_device.py PORT EDS NODE_ID

It connects, sends its boot-up message and prints `READY`; then it takes one command a line
from stdin, acts and prints `DONE <command>`:

    heartbeat MS    produce heartbeats every MS milliseconds (0: stop)
    emcy            send EMCY 2310h, register 03h, manufacturer bytes 01..05
    reset           reset (a new boot-up message)
    set I S HEX     store bytes HEX in object I (hex) sub-index S, as an SDO write would
    pdo             take up the PDO configuration a master wrote by SDO (see `take_up_pdos`);
                    `DONE pdo` is followed by the mappings in use and the EDS's
    tpdo N          transmit TPDO N with the mapped objects' values; `DONE tpdo HEX`
    rpdo N          wait until N RPDOs were applied; `DONE rpdo I:S=HEX ...`, each object
                    RPDO1 maps with the value it now holds
    quit            disconnect and exit

Any failure is a python exception: a traceback on stderr and exit code 1.
"""

import sys
import time

import canopen


def boot(node):
    """Reset (the boot-up message), then pre-operational."""
    node.nmt.send_command(0x81)
    node.nmt.send_command(0x80)


def mapping(pdo_map):
    return ",".join(f"{v.index:04X}:{v.subindex:02X}/{v.length}" for v in pdo_map.map)


def take_up_pdos(node, applied):
    """python canopen 2.4.1's LocalNode keeps what an SDO client writes in its data store, but
    its PDO maps are a cache filled once: `read()` (from_od=False, which on a LocalNode reads
    the data store through its own SDO server) takes up the configuration the master wrote;
    `read(from_od=True)` would take the EDS's values instead. A LocalNode neither fills a TPDO
    from its data store nor stores what an RPDO brings: `tpdo` and the callback here do that.
    Returns the mappings in use and those of the EDS."""
    from_eds = []
    for pdos in (node.tpdo, node.rpdo):
        pdos[1].read(from_od=True)
        from_eds.append(mapping(pdos[1]))
        pdos.read()

    def apply(pdo_map):
        for variable in pdo_map.map:
            node.set_data(variable.index, variable.subindex, variable.get_data())
        applied.append(pdo_map.cob_id)

    node.rpdo[1].add_callback(apply)
    return (f"tpdo1 {mapping(node.tpdo[1])} rpdo1 {mapping(node.rpdo[1])}; "
            f"eds: tpdo1 {from_eds[0]} rpdo1 {from_eds[1]}")


def transmit_tpdo(node, number):
    tpdo = node.tpdo[number]
    for variable in tpdo.map:
        variable.set_data(node.get_data(variable.index, variable.subindex))
    tpdo.transmit()
    return bytes(tpdo.data).hex()


def rpdo_applied(node, applied, count):
    end = time.monotonic() + 5.0
    while len(applied) < count:
        if time.monotonic() > end:
            raise TimeoutError(f"{len(applied)} RPDOs applied, not {count}")
        time.sleep(0.002)
    return " ".join(f"{v.index:04X}:{v.subindex:02X}={node.get_data(v.index, v.subindex).hex()}"
                    for v in node.rpdo[1].map)


def main():
    port, eds, node_id = int(sys.argv[1]), sys.argv[2], int(sys.argv[3])
    network = canopen.Network()
    network.connect(interface="socketcand", channel="can0", host="127.0.0.1", port=port)
    try:
        node = canopen.LocalNode(node_id, eds)
        network.add_node(node)
        node.emcy.network = network
        boot(node)
        print("READY", flush=True)
        applied = []
        for line in sys.stdin:
            words = line.split()
            if not words:
                continue
            said = ""
            if words[0] == "heartbeat":
                period = int(words[1])
                if period:
                    node.nmt.start_heartbeat(period)
                else:
                    node.nmt.stop_heartbeat()
            elif words[0] == "emcy":
                node.emcy.send(0x2310, 0x03, b"\x01\x02\x03\x04\x05")
            elif words[0] == "reset":
                boot(node)
            elif words[0] == "set":
                node.set_data(int(words[1], 16), int(words[2]), bytes.fromhex(words[3]))
            elif words[0] == "pdo":
                said = take_up_pdos(node, applied)
            elif words[0] == "tpdo":
                said = transmit_tpdo(node, int(words[1]))
            elif words[0] == "rpdo":
                said = rpdo_applied(node, applied, int(words[1]))
            elif words[0] == "quit":
                print("DONE quit", flush=True)
                return
            print(f"DONE {words[0]} {said}".rstrip(), flush=True)
    finally:
        network.disconnect()


if __name__ == "__main__":
    main()

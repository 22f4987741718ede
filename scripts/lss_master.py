"""python `canopen`'s LSS master (network.lss) against unconfigured simulated devices, through a
socketcand hub: fastscan finds each, gives it a node-ID, stores it and switches it back to
waiting, where it takes the ID and boots up; each then answers SDO at its new ID. Then the
selective switch, inquiries and bit timing (one accepted, one refused) on the first node.

Usage: lss_master.py HOST PORT FIRST_NODE_ID. Prints one line per step; exit 1 on a failure."""

import sys
import threading

import canopen
from canopen.lss import CS_INQUIRE_SERIAL_NUMBER, LssError


def identity(lss_id):
    return ":".join(f"0x{v:08X}" for v in lss_id)


def main():
    host, port, first = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    network = canopen.Network()
    network.connect(interface="socketcand", channel="can0", host=host, port=port, tcp_tune=True)
    try:
        run(network, first)
    finally:
        network.disconnect()


def run(network, first):
    lss = network.lss
    lss.send_switch_state_global(lss.WAITING_STATE)
    found = []
    node_id = first
    while True:
        ok, lss_id = lss.fast_scan()
        if not ok:
            break
        lss.configure_node_id(node_id)
        lss.store_configuration()
        node = canopen.RemoteNode(node_id, canopen.ObjectDictionary())
        network.add_node(node)
        # Leaving configuration, the unconfigured device takes its node-ID (CiA 305) and boots
        # up. The listener is in place before the switch: `nmt.wait_for_bootup` only sees a
        # boot-up that comes after it is called, and on a loaded machine the device's can come
        # first.
        booted = threading.Event()

        def on_error_control(can_id, data, timestamp):
            if data[:1] == b"\x00":
                booted.set()

        network.subscribe(0x700 + node_id, on_error_control)
        lss.send_switch_state_global(lss.WAITING_STATE)
        if not booted.wait(5):
            raise SystemExit(f"no boot-up from node {node_id} within 5 s")
        network.unsubscribe(0x700 + node_id, on_error_control)
        serial = int.from_bytes(node.sdo.upload(0x1018, 4), "little")
        print(f"found {identity(lss_id)} node {node_id} boot-up serial 0x{serial:08X}")
        found.append((lss_id, node_id))
        node_id += 1
        if len(found) > 10:
            raise SystemExit("fastscan does not end")
    print(f"{len(found)} found")
    lss_id, node_id = found[0]
    if not lss.send_switch_state_selective(*lss_id):
        raise SystemExit("no answer to switch state selective")
    print(f"selected node-ID {lss.inquire_node_id()} serial 0x{lss.inquire_lss_address(CS_INQUIRE_SERIAL_NUMBER):08X}")
    lss.configure_bit_timing(3)
    print("bit timing 250 kbit/s accepted")
    try:
        lss.configure_bit_timing(5)
        print("bit timing table entry 5 accepted")
    except LssError as e:
        print(f"bit timing table entry 5 refused: {e}")
    try:
        lss.configure_node_id(0)
        print("node-ID 0 accepted")
    except LssError as e:
        print(f"node-ID 0 refused: {e}")
    lss.send_switch_state_global(lss.WAITING_STATE)


if __name__ == "__main__":
    main()

"""python `canopen`'s node scanner on a socketcand bus: which node-IDs answer, and each one's
device type (1000h) and identity (1018h sub 1 and 2) read by SDO.

Usage: canopen_scan.py HOST PORT

Prints `found N N ...` (ascending), then one line per node: `node N 1000h 0x........ vendor
0x........ product 0x........`. Every wait has a timeout; an error ends the script on stderr.
"""

import sys
import time

import canopen

TIMEOUT = 3.0


def main():
    host, port = sys.argv[1], int(sys.argv[2])
    network = canopen.Network()
    network.connect(interface="socketcand", channel="can0", host=host, port=port, tcp_tune=True)
    try:
        network.scanner.search()
        time.sleep(1.0)
        found = sorted(set(network.scanner.nodes))
        print("found " + " ".join(str(n) for n in found), flush=True)
        for node_id in found:
            node = network.add_node(node_id, canopen.ObjectDictionary())
            node.sdo.RESPONSE_TIMEOUT = TIMEOUT
            values = [
                int.from_bytes(node.sdo.upload(index, sub), "little")
                for index, sub in ((0x1000, 0), (0x1018, 1), (0x1018, 2))
            ]
            print(
                "node %d 1000h 0x%08x vendor 0x%08x product 0x%08x" % (node_id, *values),
                flush=True,
            )
    finally:
        network.disconnect()


if __name__ == "__main__":
    main()

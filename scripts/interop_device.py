"""python canopen 2.4.1 LocalNode as a device for the edsgen master, through a socketcand hub.

Used by tests/interop_python_master.rs. Usage:

    interop_device.py PORT EDS NODE_ID

It connects, sends its boot-up message and prints `READY`; then it takes one command a line
from stdin, acts and prints `DONE <command>`:

    heartbeat MS    produce heartbeats every MS milliseconds (0: stop)
    emcy            send EMCY 2310h, register 03h, manufacturer bytes 01..05
    reset           reset (a new boot-up message)
    quit            disconnect and exit

Any failure is a python exception: a traceback on stderr and exit code 1.
"""

import sys

import canopen


def boot(node):
    """Reset (the boot-up message), then pre-operational."""
    node.nmt.send_command(0x81)
    node.nmt.send_command(0x80)


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
        for line in sys.stdin:
            words = line.split()
            if not words:
                continue
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
            elif words[0] == "quit":
                print("DONE quit", flush=True)
                return
            print(f"DONE {words[0]}", flush=True)
    finally:
        network.disconnect()


if __name__ == "__main__":
    main()

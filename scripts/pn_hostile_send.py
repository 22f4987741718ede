"""Sends the hostile frames and datagrams tests/pn_hostile.rs wrote, in order, from inside the
controller's network namespace: `F HEX` lines as raw Ethernet frames on IFACE, `U HEX` lines
as UDP datagrams to the device's RPC port (34964) at DEVICE_IP. Prints how many of each went.

usage: pn_hostile_send.py IFACE DEVICE_IP FILE
"""

import socket
import sys


def main():
    iface, device_ip, path = sys.argv[1:4]
    raw = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(0x8892))
    raw.bind((iface, 0))
    udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    frames = datagrams = refused = 0
    with open(path) as lines:
        for line in lines:
            kind, data = line.split()
            data = bytes.fromhex(data)
            try:
                if kind == "F":
                    raw.send(data.ljust(60, b"\0"))
                    frames += 1
                else:
                    udp.sendto(data, (device_ip, 34964))
                    datagrams += 1
            except OSError:
                refused += 1
    print(f"sent {frames} frames and {datagrams} datagrams ({refused} refused here)", flush=True)


main()

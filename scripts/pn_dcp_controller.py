"""The PROFINET DCP side of a controller, with pnio-dcp (pinned in scripts/python-venv.sh), for
tests/pn_dcp_python.rs: identify all on the interface that has IP, find the device whose name of
station is NAME, read its VendorID/DeviceID from the same Identify response (pnio-dcp's Device
keeps no IDs, so its own packet classes decode the raw response), set a new name of station,
read it back by Get and by Identify, set an IP and blink. One line per step on stdout.

Usage: pn_dcp_controller.py IP IFACE NAME NEW_NAME
"""
import socket
import sys

import pnio_dcp
from pnio_dcp.protocol import DCPBlock, DCPPacket, EthernetPacket

ip, iface, name, new_name = sys.argv[1:5]
dcp = pnio_dcp.DCP(ip)
found = [d for d in dcp.identify_all(timeout=2) if d.name_of_station == name]
print(f"found {len(found)} named {name}", flush=True)
mac = found[0].MAC

# The same Identify again on a raw socket of our own, decoded with pnio-dcp's packet classes.
raw = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(0x8892))
raw.bind((iface, 0))
raw.settimeout(2)
request = EthernetPacket(
    "01:0e:cf:00:00:00",
    dcp.src_mac,
    0x8892,
    payload=DCPPacket(0xFEFE, 5, 0, 0x12345678, response_delay=1, payload=bytes([0xFF, 0xFF, 0, 0])),
)
raw.send(bytes(request))
ids = None
while ids is None:
    frame = raw.recv(1600)
    eth = EthernetPacket(data=frame)
    if eth.ether_type != 0x8892 or eth.destination != dcp.src_mac:
        continue
    packet = DCPPacket(data=eth.payload)
    if packet.frame_id != 0xFEFF or packet.xid != 0x12345678:
        continue
    blocks = packet.payload
    while len(blocks) >= 6:
        block = DCPBlock(data=blocks)
        if (block.opt, block.subopt) == (2, 3):
            ids = block.payload
        blocks = blocks[4 + block.length + block.length % 2:]
print(f"vendor {ids[0]:02x}{ids[1]:02x} device {ids[2]:02x}{ids[3]:02x}", flush=True)

print(f"set name {dcp.set_name_of_station(mac, new_name).code}", flush=True)
print(f"get name {dcp.get_name_of_station(mac)}", flush=True)
print(f"identify name {dcp.identify(mac).name_of_station}", flush=True)
print(f"set ip {dcp.set_ip_address(mac, ['10.77.0.2', '255.255.255.0', '0.0.0.0']).code}", flush=True)
print(f"get ip {dcp.get_ip_address(mac)}", flush=True)
print(f"blink {dcp.blink(mac).code}", flush=True)

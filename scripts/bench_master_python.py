"""python canopen 2.4.1 master and LocalNode through a socketcand hub: the SDO round trip that
examples/master_bench.rs compares the edsgen master with.

    bench_master_python.py PORT EDS N

Prints one line: the median and mean of N expedited uploads of 1000h, in microseconds.
"""
import statistics
import sys
import time

import canopen

port, eds, count = int(sys.argv[1]), sys.argv[2], int(sys.argv[3])
device_net = canopen.Network()
device_net.connect(interface="socketcand", channel="can0", host="127.0.0.1", port=port)
master_net = canopen.Network()
master_net.connect(interface="socketcand", channel="can0", host="127.0.0.1", port=port)
try:
    device_net.add_node(canopen.LocalNode(9, eds))
    remote = master_net.add_node(canopen.RemoteNode(9, eds))
    remote.sdo.upload(0x1000, 0)
    times = []
    for _ in range(count):
        start = time.perf_counter()
        remote.sdo.upload(0x1000, 0)
        times.append(time.perf_counter() - start)
    median = statistics.median(times) * 1e6
    mean = statistics.mean(times) * 1e6
    print(f"{median:.0f} {mean:.0f}")
finally:
    master_net.disconnect()
    device_net.disconnect()

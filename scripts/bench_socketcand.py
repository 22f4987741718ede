"""SDO round trips of python `canopen` 2.4.1 through a socketcand hub: the python side of
examples/socketcand_bench.rs, which runs the hub and the device and prints the figures.

    bench_socketcand.py master PORT EDS NODE_ID N   N SDO transactions on 6042h (a download then
                                                    an upload, alternately, each checked);
                                                    prints RESULT <json>
    bench_socketcand.py serve PORT EDS NODE_ID      a python LocalNode from EDS, served until
                                                    stdin closes; prints READY once it listens
"""

import json
import logging
import statistics
import sys
import time

import canopen

logging.disable(logging.CRITICAL)


def connect(port):
    network = canopen.Network()
    network.connect(interface="socketcand", channel="can0", host="127.0.0.1", port=port,
                    tcp_tune=True)
    return network


def master(network, eds, node_id, count):
    node = canopen.RemoteNode(node_id, eds)
    network.add_node(node)
    node.sdo.RESPONSE_TIMEOUT = 1.0
    round_trips = []
    failures = 0
    written = None
    start = time.perf_counter()
    for i in range(count):
        before = time.perf_counter()
        try:
            if i % 2 == 0:
                written = (i * 7919) % 65536 - 32768
                node.sdo[0x6042].raw = written
            elif node.sdo[0x6042].raw != written:
                failures += 1
        except Exception:  # a timeout or an abort: counted, not fatal
            failures += 1
        round_trips.append(time.perf_counter() - before)
    elapsed = time.perf_counter() - start
    round_trips.sort()
    return {
        "transactions": count,
        "failures": failures,
        "median_us": round(statistics.median(round_trips) * 1e6),
        "p99_us": round(round_trips[int(len(round_trips) * 0.99)] * 1e6),
        "seconds": round(elapsed, 3),
    }


def main():
    mode, port, eds, node_id = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
    network = connect(port)
    try:
        if mode == "master":
            result = master(network, eds, node_id, int(sys.argv[5]))
            print("RESULT " + json.dumps(result), flush=True)
        elif mode == "serve":
            network.add_node(canopen.LocalNode(node_id, eds))
            print("READY", flush=True)
            sys.stdin.read()
        else:
            raise SystemExit(f"unknown mode {mode}")
    finally:
        network.disconnect()


if __name__ == "__main__":
    main()

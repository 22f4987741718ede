"""SDO round trips through a socketcand hub, for tests/sdo_rounds.rs.

Usage:
  sdo_rounds.py master HOST PORT NODE_ID COUNT   COUNT expedited uploads of 1018h:01; prints
                                                 `failures N`, then `median_us N`
  sdo_rounds.py serve HOST PORT NODE_ID EDS      python canopen's LocalNode of EDS as the node,
                                                 until standard input closes (the baseline)
"""

import statistics
import sys
import time

import canopen


def connect(host, port):
    network = canopen.Network()
    network.connect(interface="socketcand", channel="can0", host=host, port=int(port), tcp_tune=True)
    return network


def master(host, port, node_id, count):
    network = connect(host, port)
    try:
        node = canopen.RemoteNode(int(node_id), canopen.ObjectDictionary())
        node.sdo.RESPONSE_TIMEOUT = 2.0
        network.add_node(node)
        failures, rounds = 0, []
        for _ in range(int(count)):
            start = time.perf_counter()
            try:
                node.sdo.upload(0x1018, 1)
            except Exception:  # a timeout or an abort: counted, the run goes on
                failures += 1
                continue
            rounds.append(time.perf_counter() - start)
        print("failures", failures)
        print("median_us", round(statistics.median(rounds) * 1e6) if rounds else 0)
    finally:
        network.disconnect()


def serve(host, port, node_id, eds):
    network = connect(host, port)
    try:
        network.create_node(int(node_id), eds)
        print("serving", flush=True)
        sys.stdin.read()
    finally:
        network.disconnect()


if __name__ == "__main__":
    mode, args = sys.argv[1], sys.argv[2:]
    {"master": master, "serve": serve}[mode](*args)

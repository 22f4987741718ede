#!/usr/bin/env python3
"""A python-can 4.6.1 socketcand client that stops reading, for the hub test
(tests/hub_python_slow_reader.rs): it connects to HOST PORT on can0, prints `READY`, reads
nothing until a line comes on standard input, then reads until the frame 7FFh and prints
`RESULT {json}`: the frames and error frames it received, the error frames' identifiers, and
whether the last frame was 7FFh. The hub dropped frames for it meanwhile: python-can must take
the hub's report (an error frame) in its stride.
"""
import json
import sys
import time

import can


def main():
    host, port = sys.argv[1], int(sys.argv[2])
    bus = can.Bus(interface="socketcand", host=host, port=port, channel="can0")
    print("READY", flush=True)
    sys.stdin.readline()
    frames, errors, error_ids, last = 0, 0, [], None
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        message = bus.recv(timeout=5)
        if message is None:
            break
        if message.is_error_frame:
            errors += 1
            error_ids.append(message.arbitration_id)
            continue
        frames += 1
        last = message.arbitration_id
        if last == 0x7FF:
            break
    bus.shutdown()
    result = {"frames": frames, "errors": errors, "error_ids": sorted(set(error_ids)), "last": last}
    print("RESULT " + json.dumps(result), flush=True)


if __name__ == "__main__":
    main()

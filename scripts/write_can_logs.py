#!/usr/bin/env python3
"""Writes one CANopen session as CAN logs with python-can's own writers, for the decode tests
(tests/decode_python_can.rs): candump -L (session.log), Vector ASC (session.asc), PCAN TRC 1.0
(session-1.0.trc) and 2.1 (session-2.1.trc), into the folder given as the only argument.

The frames are 1 ms apart from 1764000000 s (whole milliseconds, as TRC 1.0 keeps them);
the ASC writer dates its triggerblock in local time, so run this with TZ=UTC. python-can's TRC
writer leaves out CAN FD and error frames (it warns), the other writers keep them.
"""
import logging
import sys
from pathlib import Path

import can
from can.io.trc import TRCFileVersion

START = 1764000000.0

# (identifier, data, options): the session, node 5, no description needed.
FRAMES = [
    (0x000, [0x01, 0x05], {}),
    (0x705, [0x7F], {}),
    (0x605, [0x2B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0x00, 0x00], {}),
    (0x585, [0x60, 0x17, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00], {}),
    # An upload request of 4 bytes, as some masters send it.
    (0x605, [0x40, 0x18, 0x10, 0x01], {}),
    (0x585, [0x43, 0x18, 0x10, 0x01, 0x78, 0x56, 0x34, 0x12], {}),
    # A segmented upload of "edsgen-log", its last segment in a 4-byte frame.
    (0x605, [0x40, 0x08, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00], {}),
    (0x585, [0x41, 0x08, 0x10, 0x00, 0x0A, 0x00, 0x00, 0x00], {}),
    (0x605, [0x60, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00], {}),
    (0x585, [0x00] + list(b"edsgen-"), {}),
    (0x605, [0x70, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00], {}),
    (0x585, [0x19] + list(b"log"), {}),
    (0x7E5, [0x04, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00], {}),
    (0x7E5, [0x5A, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00], {}),
    (0x7E4, [0x5A, 0x23, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00], {}),
    (0x080, [], {}),
    (0x185, [0x01, 0x02], {}),
    (0x085, [0x10, 0x81, 0x11, 0x00, 0x00, 0x00, 0x00, 0x00], {}),
    (0x18FF0005, [0xAA], {"is_extended_id": True}),
    (0x123, list(range(12)), {"is_fd": True}),
    (0x000, [], {"is_error_frame": True}),
    (0x705, [0x05], {"is_rx": False}),
]


def messages():
    for n, (arbitration_id, data, options) in enumerate(FRAMES):
        options = {"is_extended_id": False, **options}
        yield can.Message(
            timestamp=START + n / 1000, arbitration_id=arbitration_id, data=data, **options
        )


def write(writer):
    for message in messages():
        writer.on_message_received(message)
    writer.stop()


def main():
    # The TRC writer's warnings about the frames it leaves out are expected.
    logging.getLogger("can").setLevel(logging.ERROR)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    write(can.CanutilsLogWriter(out / "session.log"))
    write(can.ASCWriter(out / "session.asc"))
    for version, name in [(TRCFileVersion.V1_0, "1.0"), (TRCFileVersion.V2_1, "2.1")]:
        writer = can.TRCWriter(out / f"session-{name}.trc")
        writer.file_version = version
        write(writer)
    print("written")


if __name__ == "__main__":
    main()

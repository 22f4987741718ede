"""Hostile telegrams at a simulated DP slave, then pyprofibus as its master:
`python scripts/dp_hostile.py GSD ADDRESS [COUNT [SEED]]` (COUNT 3000, SEED 34).

On the slave's line (see `dp_master.py`, whose pseudo-terminals and master this uses): waits
until the slave answers an FDL status request (`ALIVE`), sends COUNT telegrams mutated from a
good start-up and exchange (FDL status, Slave_Diag, Set_Prm, Chk_Cfg, Get_Cfg, Data_Exchange,
Global_Control: bytes flipped, cut, lengthened, lengths and addresses changed, random bytes),
in bursts with the line idle between them, deterministic from SEED, reading what the slave
answers (`SENT <count> ANSWERS <count>`); then a header announcing 249 bytes and silence, after
which the next FDL status must be answered at once (`ALIVE_AFTER_HOSTILE`); then pyprofibus
takes the slave to data exchange and through the card's steps, as `dp_master.py` prints them.
Exit 0 when every step was reached, 1 otherwise.
"""

import os
import random
import select
import sys
import time

import dp_master


def telegram(body):
    """SD1 for a body of 3 bytes, else SD2, with FCS and ED."""
    fcs = sum(body) & 0xFF
    if len(body) == 3:
        return bytes([0x10] + body + [fcs, 0x16])
    return bytes([0x68, len(body), len(body), 0x68] + body + [fcs, 0x16])


def recorded(address):
    """A master's (station 1) good start-up and exchange with the slave at `address`."""
    da, sa = address | 0x80, 0x81
    srd = lambda fcb: 0x5C | (0x20 if fcb else 0)
    outputs = [0, 1, 0, 10, 0, 0, 0, 0, 0, 1, 0x03, 0xE8] + [0] * 20
    return [
        telegram([address, 1, 0x49]),
        telegram([da, sa, srd(0), 60, 62]),
        telegram([da, sa, srd(1), 61, 62, 0x88, 10, 10, 11, 0x03, 0x50, 0]),
        telegram([da, sa, srd(0), 62, 62, 0xF3, 0xFB]),
        telegram([da, sa, srd(1), 59, 62]),
        telegram([address, 1, srd(0)] + outputs),
        telegram([0xFF, sa, 0x46, 58, 62, 0x08, 0]),
    ]


def mutate(rng, frame):
    frame = bytearray(frame)
    kind = rng.randrange(8)
    if kind == 0:
        frame[rng.randrange(len(frame))] ^= 1 << rng.randrange(8)
    elif kind == 1:
        frame = frame[: rng.randrange(len(frame))]
    elif kind == 2:
        frame += bytes(rng.randrange(256) for _ in range(rng.randrange(1, 20)))
    elif kind == 3 and frame[0] == 0x68:
        frame[1] = frame[2] = rng.randrange(256)
    elif kind == 4:
        frame[rng.randrange(len(frame))] = rng.randrange(256)
    elif kind == 5:
        frame = bytearray(rng.randrange(256) for _ in range(rng.randrange(1, 60)))
    elif kind == 6:
        frame = bytearray([0x68, 0xF9, 0xF9, 0x68]) + frame
    return bytes(frame)


def drain(fd):
    """The bytes the slave sent, without waiting."""
    got = b""
    while select.select([fd], [], [], 0)[0]:
        got += os.read(fd, 4096)
    return got


def alive(fd, address, seconds):
    """Whether the slave answers an FDL status request within `seconds` (one request every
    100 ms, with the line idle before each)."""
    status = telegram([address, 1, 0x49])
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        time.sleep(0.05)
        drain(fd)
        os.write(fd, status)
        ready = select.select([fd], [], [], 0.1)[0]
        if ready and telegram([1, address, 0x00]) in os.read(fd, 4096):
            return True
    return False


def hostile(fd, address):
    count = int(sys.argv[3]) if len(sys.argv) > 3 else 3000
    seed = int(sys.argv[4]) if len(sys.argv) > 4 else 34
    if not alive(fd, address, 20):
        print("NOT_ALIVE before", flush=True)
        sys.exit(1)
    print("ALIVE", flush=True)
    rng = random.Random(seed)
    good = recorded(address)
    answers = b""
    for n in range(count):
        os.write(fd, mutate(rng, rng.choice(good)))
        if n % 25 == 24:
            time.sleep(0.025)
            answers += drain(fd)
    time.sleep(0.05)
    answers += drain(fd)
    print("SENT", count, "ANSWERED", len(answers) > 0, flush=True)
    # A header announcing 249 bytes, silence, then one request: answered at once.
    os.write(fd, bytes([0x68, 0xF9, 0xF9, 0x68]))
    time.sleep(0.05)
    os.write(fd, telegram([address, 1, 0x49]))
    ready = select.select([fd], [], [], 0.5)[0]
    if not (ready and os.read(fd, 4096) == telegram([1, address, 0x00])):
        print("NOT_ALIVE after the 249-byte header", flush=True)
        sys.exit(1)
    print("ALIVE_AFTER_HOSTILE", flush=True)


if __name__ == "__main__":
    sys.exit(dp_master.main(hostile))

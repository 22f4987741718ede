"""The IO controller side of a PROFINET test, with profinet-py (pinned in scripts/python-venv.sh),
for tests/pn_profinet_py.rs: profinet-py's own `cyclic` path (profinet/cli.py cmd_cyclic), step
by step, with outputs of our own: DCP identify by name, a device access Connect, Read 0xF000
RealIdentificationData, Release; the Connect with IOCRs built from the GSDML and the real
identification, a Write of record 256 and its Read, PrmEnd, ApplicationReady; then RT frames:
CW 1 (run forward) with PZD2 500 (5.00 Hz) until the running frequency reaches it, a PKW read
of P00.11, CW 5 (stop) until the drive stops; then, with profinet-py's alarm listener on the
AR's AlarmCR, the drive's fault (raised by the test through the device's standard input) as a
Diagnosis alarm, which the listener acknowledges, CW 7 (fault reset) until the fault is gone
(the test removes its cause) and the Diagnosis disappears alarm; Release. One line per step on
stdout, values exact so that the test can assert them.

Usage: pn_cyclic_controller.py IFACE NAME GSDML
"""
import queue
import struct
import sys
import time

from profinet import rpc
from profinet.cyclic import CyclicController
from profinet.gsdml import load_gsdml
from profinet.rpc import IOCRSetup
from profinet.rt import build_iocr_configs
from profinet.util import ethernet_socket, get_mac, s2mac

iface, name, gsdml = sys.argv[1:4]
CYCLE_MS = 8

sock = ethernet_socket(iface, 3)
src = get_mac(iface)
info = rpc.get_station_info(sock, src, name)
print(f"found {info.name} at {info.ip}", flush=True)

conn = rpc.RPCCon(info)
conn.connect(src)
slots = conn.discover_slots()
print("real " + " ".join(f"{s.slot}:{s.subslot:#x}={s.module_ident:#x}/{s.submodule_ident:#x}" for s in slots), flush=True)
conn.close()
time.sleep(0.5)

io_slots = load_gsdml(gsdml).build_io_slots_from_device(slots)
print("io " + " ".join(f"{s.slot}:{s.subslot:#x}={s.input_length}/{s.output_length}" for s in io_slots), flush=True)
setup = IOCRSetup(
    slots=io_slots,
    send_clock_factor=32,
    reduction_ratio=CYCLE_MS,
    watchdog_factor=6,
    data_hold_factor=6,
)
conn = rpc.RPCCon(info)
result = conn.connect(src, iocr_setup=setup)
print(f"connected input {result.input_frame_id:#06x} output {result.output_frame_id:#06x}", flush=True)

# Record 256: the received PZD meanings P16.32-P16.42; PZD2 stays the set frequency (1).
record = struct.pack(">11H", 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0)
conn.write(api=0, slot=1, subslot=1, idx=256, data=record)
back = conn.read(api=0, slot=1, subslot=1, idx=256).payload
print(f"record 256 {back.hex()}", flush=True)

conn.prm_end()
print("prm end", flush=True)
conn.application_ready(timeout=10)
print("application ready", flush=True)

input_iocr, output_iocr = build_iocr_configs(
    setup.slots,
    result.input_frame_id,
    result.output_frame_id,
    setup.send_clock_factor,
    setup.reduction_ratio,
)
cyclic = CyclicController(
    interface=iface,
    src_mac=src,
    dst_mac=s2mac(info.mac),
    input_iocr=input_iocr,
    output_iocr=output_iocr,
)


def words(pkw=(0, 0, 0, 0), cw=0, pzd2=0):
    return struct.pack(">16H", *pkw, cw, pzd2, *([0] * 10))


def inputs():
    data = cyclic.get_input_data(1, 1)
    return struct.unpack(">16H", data) if data and len(data) == 32 else None


def until(output, done, seconds):
    cyclic.set_output_data(1, 1, output)
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        seen = inputs()
        if seen is not None and done(seen):
            return seen
        time.sleep(CYCLE_MS / 1000)
    raise SystemExit(f"not within {seconds} s: {inputs()}")


alarms = queue.Queue()
listener = conn.create_alarm_listener(iface)
if listener is None:
    raise SystemExit("no AlarmCR established")
listener.add_callback(alarms.put)
listener.start()


def alarm(seconds):
    try:
        a = alarms.get(timeout=seconds)
    except queue.Empty:
        raise SystemExit(f"no alarm within {seconds} s")
    return (
        f"alarm {a.alarm_type:#06x} slot {a.slot_number} subslot {a.subslot_number} "
        f"seq {a.alarm_sequence_number} payload {a.raw_payload.hex()}"
    )


cyclic.set_output_data(1, 1, words())
cyclic.start()
seen = until(words(), lambda w: True, 5)
print(f"data exchange sw {seen[4] & 0xFF}", flush=True)
seen = until(words(cw=1, pzd2=500), lambda w: w[5] == 500, 20)
print(f"run sw {seen[4] & 0xFF} frequency {seen[5]}", flush=True)
seen = until(words(pkw=(1, 0x000B, 0, 0), cw=1, pzd2=500), lambda w: w[0] == 1, 5)
print(f"pkw read {seen[1]:#06x} = {seen[3]}", flush=True)
seen = until(words(cw=5), lambda w: w[4] & 0xFF == 3, 20)
print(f"stop sw {seen[4] & 0xFF} frequency {seen[5]}", flush=True)
print("waiting for an alarm", flush=True)
print(alarm(20), flush=True)
seen = until(words(), lambda w: w[4] & 0xFF == 4, 5)
print(f"fault sw {seen[4] & 0xFF}", flush=True)
# The drive takes a command when the CW changes: CW 7 and 0 in turn until the cause is gone.
deadline = time.monotonic() + 20
cw = 7
while (inputs() or (0,) * 16)[4] & 0xFF != 3:
    if time.monotonic() > deadline:
        raise SystemExit(f"no fault reset within 20 s: {inputs()}")
    cyclic.set_output_data(1, 1, words(cw=cw))
    cw = 7 - cw
    time.sleep(0.1)
seen = inputs()
print(f"reset sw {seen[4] & 0xFF}", flush=True)
print(alarm(10), flush=True)
time.sleep(0.5)
listener.stop()
cyclic.stop()
print(f"frames in {'yes' if cyclic.stats.frames_received > 0 else 'no'}", flush=True)
conn.close()
print("released", flush=True)

"""The IO controller side of tests/pn_modules.rs, with profinet-py (pinned in
scripts/python-venv.sh), on a simulated modular device: profinet-py's own `cyclic` path
(profinet/cli.py cmd_cyclic) with outputs of our own. DCP identify by name, a device access
Connect, Read 0xF000 RealIdentificationData (the modules the device was given), Release; the
Connect with IOCRs built from the GSDML and that real identification, PrmEnd,
ApplicationReady; then RT frames with OUT_SLOT's output data set to HEX until IN_SLOT's input
data reads HEX (the device loops its outputs back to its inputs); Release. One line per step
on stdout, values exact so that the test can assert them.

Usage: pn_modules_controller.py IFACE NAME GSDML OUT_SLOT IN_SLOT HEX
"""
import sys
import time

from profinet import rpc
from profinet.cyclic import CyclicController
from profinet.gsdml import load_gsdml
from profinet.rpc import IOCRSetup
from profinet.rt import build_iocr_configs
from profinet.util import ethernet_socket, get_mac, s2mac

iface, name, gsdml, out_slot, in_slot, wanted = sys.argv[1:7]
out_slot, in_slot, wanted = int(out_slot), int(in_slot), bytes.fromhex(wanted)
CYCLE_MS = 8

sock = ethernet_socket(iface, 3)
src = get_mac(iface)
info = rpc.get_station_info(sock, src, name)
print(f"found {info.name} at {info.ip}", flush=True)

conn = rpc.RPCCon(info)
conn.connect(src)
slots = conn.discover_slots()
modules = sorted({(s.slot, s.module_ident) for s in slots if s.slot != 0})
print("modules " + " ".join(f"{slot}={ident:#x}" for slot, ident in modules), flush=True)
conn.close()
time.sleep(0.5)

io_slots = load_gsdml(gsdml).build_io_slots_from_device(slots)
io = [s for s in io_slots if s.input_length or s.output_length]
print("io " + " ".join(f"{s.slot}.{s.subslot}={s.input_length}/{s.output_length}" for s in io), flush=True)
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
conn.prm_end()
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
cyclic.set_output_data(out_slot, 1, wanted)
cyclic.start()
deadline = time.monotonic() + 10
seen = None
while time.monotonic() < deadline:
    seen = cyclic.get_input_data(in_slot, 1)
    if seen == wanted:
        break
    time.sleep(CYCLE_MS / 1000)
else:
    raise SystemExit(f"input {in_slot}.1 not {wanted.hex()} within 10 s: {seen}")
print(f"output {out_slot}.1={wanted.hex()} input {in_slot}.1={seen.hex()}", flush=True)
cyclic.stop()
conn.close()
print("released", flush=True)

"""python `canopen` as the master of one simulated device, through a socketcand hub.

Usage: canopen_master.py HOST PORT PLAN.json

PLAN (written by tests/simulate_python.rs from the device's dictionary) holds the node-ID, the
objects python's object dictionary needs (index, record or not, sub-indices with data type and
access) and the entries to exercise. Every step prints one line; the test compares them exactly.
Every wait has a timeout; an error ends the script with the failing step on stderr.
"""

import json
import sys
import threading
import time

import canopen
from canopen.objectdictionary import ODRecord, ODVariable, ObjectDictionary

TIMEOUT = 3.0


def build_od(objects):
    od = ObjectDictionary()
    for obj in objects:
        if obj["record"]:
            record = ODRecord(obj["name"], obj["index"])
            for sub, data_type, access, name in obj["subs"]:
                var = ODVariable(name, obj["index"], sub)
                var.data_type = data_type
                var.access_type = access
                record.add_member(var)
            od.add_object(record)
        else:
            sub, data_type, access, name = obj["subs"][0]
            var = ODVariable(name, obj["index"], sub)
            var.data_type = data_type
            var.access_type = access
            od.add_object(var)
    return od


def entry(text):
    index, sub = text.split(":")
    return int(index, 16), int(sub, 16)


class States:
    """Every NMT state the node reports (boot-up and heartbeats), for waits without races."""

    def __init__(self):
        self.seen = []
        self.changed = threading.Condition()

    def __call__(self, state):
        with self.changed:
            self.seen.append(state)
            self.changed.notify_all()

    def wait_for(self, state, after):
        deadline = time.time() + TIMEOUT
        with self.changed:
            while state not in self.seen[after:]:
                left = deadline - time.time()
                if left <= 0:
                    raise TimeoutError(f"no NMT state {state:#x} (saw {self.seen[after:]})")
                self.changed.wait(left)


def main():
    host, port, plan_path = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    with open(plan_path) as f:
        plan = json.load(f)
    node_id = plan["node_id"]
    network = canopen.Network()
    network.connect(interface="socketcand", channel="can0", host=host, port=port, tcp_tune=True)
    try:
        node = canopen.RemoteNode(node_id, build_od(plan["objects"]))
        node.sdo.RESPONSE_TIMEOUT = TIMEOUT
        network.add_node(node)
        run(network, node, plan)
    finally:
        network.disconnect()


def run(network, node, plan):
    states = States()
    node.nmt.add_heartbeat_callback(states)

    # NMT reset node: the boot-up message.
    mark = len(states.seen)
    node.nmt.send_command(0x81)
    states.wait_for(0x00, mark)
    print("boot-up")

    # Heartbeat every 50 ms, set by an expedited SDO write.
    mark = len(states.seen)
    node.sdo.download(0x1017, 0, (50).to_bytes(2, "little"))
    states.wait_for(0x7F, mark)
    print("heartbeat pre-operational")

    # Expedited upload, and a write read back.
    print("read 1000:00", node.sdo.upload(0x1000, 0).hex())
    index, sub = entry(plan["rw"]["entry"])
    node.sdo.download(index, sub, bytes.fromhex(plan["rw"]["value"]))
    print("write", plan["rw"]["entry"], node.sdo.upload(index, sub).hex())

    # Segmented and block transfers, both ways.
    if plan.get("bytes"):
        index, sub = entry(plan["bytes"]["entry"])
        value = bytes.fromhex(plan["bytes"]["value"])
        node.sdo.download(index, sub, value)
        print("segmented", plan["bytes"]["entry"], node.sdo.upload(index, sub).hex())
        with node.sdo.open(index, sub, "wb", size=len(value), block_transfer=True) as f:
            f.write(value[::-1])
        with node.sdo.open(index, sub, "rb", block_transfer=True) as f:
            print("block", plan["bytes"]["entry"], f.read().hex())

    # An abort.
    try:
        node.sdo.upload(*entry(plan["absent"]))
        print("no abort")
    except canopen.SdoAbortedError as e:
        print(f"abort {e.code:08X}")

    # PDOs configured through python's PDO API (where the description lets their mapping
    # change: sub-index 0 of 1A00h/1600h writable).
    tpdo, rpdo = node.tpdo[1], node.rpdo[1]
    if "tpdo" in plan:
        tpdo.read(from_od=False)
        tpdo.clear()
        tpdo.add_variable(*entry(plan["tpdo"]))
        tpdo.trans_type = 1
        tpdo.enabled = True
        tpdo.save()
    if "rpdo" in plan:
        rpdo.read(from_od=False)
        rpdo.clear()
        rpdo.add_variable(*entry(plan["rpdo"]["entry"]))
        rpdo.trans_type = 255
        rpdo.enabled = True
        rpdo.save()

    mark = len(states.seen)
    node.nmt.state = "OPERATIONAL"
    states.wait_for(0x05, mark)
    print("operational")

    if "tpdo" in plan:
        # TPDO1 on SYNC.
        time.sleep(0.05)
        network.sync.transmit()
        tpdo.wait_for_reception(TIMEOUT)
        print("tpdo", plan["tpdo"], tpdo.data.hex())

    if "rpdo" in plan:
        # RPDO1 into the dictionary, read back.
        network.send_message(rpdo.cob_id, bytes.fromhex(plan["rpdo"]["value"]))
        deadline = time.time() + TIMEOUT
        index, sub = entry(plan["rpdo"]["entry"])
        while node.sdo.upload(index, sub).hex() != plan["rpdo"]["value"]:
            if time.time() > deadline:
                break
            time.sleep(0.01)
        print("rpdo", plan["rpdo"]["entry"], node.sdo.upload(index, sub).hex())

        # An RPDO shorter than its mapping: EMCY 8210h (if the device has an EMCY COB-ID).
        # The log is searched from before the send: `emcy.wait` sees only emergencies that
        # arrive while it waits, and this one may come first.
        mark = len(node.emcy.log)
        network.send_message(rpdo.cob_id, b"")
        deadline = time.time() + (TIMEOUT if plan["emcy"] else 0.3)
        emcy = None
        while emcy is None and time.time() < deadline:
            emcy = next((e for e in node.emcy.log[mark:] if e.code == 0x8210), None)
            time.sleep(0.01)
        print("emcy", f"{emcy.code:04X}" if emcy else "none")

    mark = len(states.seen)
    node.nmt.state = "STOPPED"
    states.wait_for(0x04, mark)
    print("stopped")


if __name__ == "__main__":
    main()

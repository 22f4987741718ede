"""Dumps what python `canopen` (2.4.1) makes of EDS/DCF files, for tests/python_diff.rs.

Usage: canopen_dump.py FILE...

Prints one JSON array with one entry per file, in the subset of the `edsgen dump` schema that python
has: {"file", "objects": [{"index", "name", "object_type", "dummy", "subs": [{"sub", "name",
"data_type", "access", "pdo_mapping", "default"}]}]}, or {"file", "error"} when the import fails.

- object_type: 7 for a python ODVariable (python does not keep VAR vs DOMAIN), 8 ODArray, 9 ODRecord.
- lazy (arrays): the entry python creates on access for a sub-index the array does not hold (from
  sub-index 1; `name_prefix` + "_" + the sub-index in lowercase hex), as python's own `arr[i]`
  gives it.
- dummy: the object was created by python from [DummyUsage] (DummyNNNN=1), not from a section.
- default: as python holds it (integers exact, floats, strings, bytes as lowercase hex, null). A
  default written with $NODEID becomes {"nodeid_offset": N}, N computed from `default_raw` the way
  python 2.4.1 evaluates it (spaces removed, `+$NODEID`/`$NODEID+` removed, int(x, 0)), or null when
  python cannot evaluate it.
"""
import json
import logging
import math
import re
import sys

import canopen
from canopen.objectdictionary import ODArray, ODRecord, ODVariable

logging.disable(logging.CRITICAL)


def nodeid_offset(raw):
    text = raw.replace(" ", "").upper()
    try:
        return int(re.sub(r"\+?\$NODEID\+?", "", text), 0)
    except ValueError:
        return None


def json_value(value):
    if value is None:
        return None
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, int):
        return value
    if isinstance(value, float):
        if math.isnan(value) or math.isinf(value):
            return repr(value)
        return value
    if isinstance(value, (bytes, bytearray)):
        return bytes(value).hex()
    return str(value)


def default_of(var):
    raw = getattr(var, "default_raw", None)
    if raw is not None and "$NODEID" in raw:
        offset = nodeid_offset(raw)
        return None if offset is None else {"nodeid_offset": offset}
    return json_value(var.default)


def sub_entry(var):
    return {
        "sub": var.subindex,
        "name": var.name,
        "data_type": var.data_type,
        "access": var.access_type,
        "pdo_mapping": bool(var.pdo_mappable),
        "default": default_of(var),
    }


def object_entry(obj):
    if isinstance(obj, ODVariable):
        dummy = (
            1 <= obj.index <= 7
            and obj.name == f"Dummy{obj.index:04d}"
            and obj.access_type == "const"
            and obj.default is None
        )
        return {
            "index": obj.index,
            "name": obj.name,
            "object_type": 7,
            "dummy": dummy,
            "subs": [sub_entry(obj)],
        }
    object_type = 8 if isinstance(obj, ODArray) else 9
    return {
        "index": obj.index,
        "name": obj.name,
        "object_type": object_type,
        "dummy": False,
        "subs": [sub_entry(obj.subindices[i]) for i in sorted(obj.subindices)],
        "lazy": lazy_entry(obj),
    }


def lazy_entry(obj):
    """What an ODArray answers for a sub-index it does not hold: python makes it on access from
    sub-index 1, named "<sub 1 name>_<sub-index in lowercase hex>". Null when it cannot."""
    if not isinstance(obj, ODArray) or 1 not in obj.subindices:
        return None
    missing = next((i for i in range(2, 256) if i not in obj.subindices), None)
    if missing is None:
        return None
    entry = sub_entry(obj[missing])
    del entry["sub"]
    entry["name_prefix"] = obj.subindices[1].name
    del entry["name"]
    return entry


def dump(path):
    try:
        od = canopen.import_od(path)
    except Exception as error:  # python's own verdict on the file, reported as data
        return {"file": path, "error": f"{type(error).__name__}: {error}"}
    objects = [object_entry(od.indices[index]) for index in sorted(od.indices)]
    return {"file": path, "objects": objects}


def main():
    json.dump([dump(path) for path in sys.argv[1:]], sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()

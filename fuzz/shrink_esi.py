#!/usr/bin/env python3
"""Shrink an ESI (EtherCAT ESI XML) file into a fuzz seed that fits libFuzzer's -max_len.

Real ESI files run from 1 KB to 4 MB, mostly repeated Device, Object, DataType and PDO elements and
hex images. A seed cut at -max_len is no longer well-formed XML, so the reader would stop at the
parser. This keeps the file's structure (prolog, vendor, groups) and, in its first two devices,
the first few dictionary objects, the data types those reference (and the ones those reference),
the first few RxPdo/TxPdo and modules, with images emptied; as text, bytes kept as they are (the
file is handled as ISO-8859-1, which maps every byte to itself, so UTF-8 files stay UTF-8).

Usage: shrink_esi.py IN OUT [MAX_BYTES]
"""
import re
import sys


def element(name):
    """An element `name` (any prefix) with its content; not one whose name only starts so."""
    return re.compile(r"<((?:\w+:)?%s)\b[^>]*?(?:/>|>.*?</\1\s*>)" % name, re.S)


DEVICE = element("Device")
OBJECT = element("Object")
DATA_TYPE = element("DataType")
PDO = element("(?:RxPdo|TxPdo)")
MODULE = element("Module")
IMAGE = re.compile(r"(<(?:\w+:)?(?:ImageData16x14|ImageData32x32|ImageFile16x14)\b[^>]*>)[^<]*", re.S)
NAME = re.compile(r"<(?:\w+:)?Name\b[^>]*>([^<]*)<")
TYPE = re.compile(r"<(?:\w+:)?(?:Type|BaseType)\b[^>]*>([^<]*)<")


def keep_first(pattern, text, keep):
    """`text` with the matches of `pattern` after the first `keep` removed."""
    count = [0]

    def sub(match):
        count[0] += 1
        return match.group(0) if count[0] <= keep else ""

    return pattern.sub(sub, text)


def shrink(text, keep):
    text = IMAGE.sub(r"\1", text)
    text = keep_first(DEVICE, text, 2)
    text = keep_first(OBJECT, text, keep)
    text = keep_first(PDO, text, max(keep // 4, 1))
    text = keep_first(MODULE, text, max(keep // 8, 1))
    # The data types the kept objects name, and the ones those name in turn.
    used = set(TYPE.findall(DATA_TYPE.sub("", text)))
    elements = [m.group(0) for m in DATA_TYPE.finditer(text)]
    changed = True
    while changed:
        changed = False
        for body in elements:
            names = NAME.findall(body[:300])
            if names and names[0] in used:
                for t in TYPE.findall(body):
                    if t not in used:
                        used.add(t)
                        changed = True

    def data_type_sub(match):
        names = NAME.findall(match.group(0)[:300])
        return match.group(0) if not names or names[0] in used else ""

    text = DATA_TYPE.sub(data_type_sub, text)
    return re.sub(r"\n\s*\n", "\n", text)


def main():
    src, dst = sys.argv[1], sys.argv[2]
    limit = int(sys.argv[3]) if len(sys.argv) > 3 else 65536
    raw = open(src, "rb").read()
    if len(raw) <= limit:
        open(dst, "wb").write(raw)
        return
    text = raw.decode("latin-1")
    keep = 64
    while keep > 0:
        out = shrink(text, keep).encode("latin-1")
        if len(out) <= limit:
            open(dst, "wb").write(out)
            return
        keep //= 2
    open(dst, "wb").write(shrink(text, 1).encode("latin-1")[:limit])


if __name__ == "__main__":
    main()

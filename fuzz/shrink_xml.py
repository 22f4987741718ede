#!/usr/bin/env python3
"""Shrink an XDD/XDC file into a fuzz seed that fits libFuzzer's -max_len.

Real XDD files are 100-600 KB, mostly repeated CANopenObject and parameter elements. A seed cut at
-max_len is no longer well-formed XML, so the reader stops at the parser. This keeps the file's
structure (header, identity, data types, network management) and only the first few objects and
the parameters and data types they reference, as text (namespaces, prefixes and attribute order untouched).

Usage: shrink_xml.py IN OUT [MAX_BYTES]
"""
import re
import sys

OBJECT = re.compile(r"<(?:\w+:)?CANopenObject\b[^>]*?(?:/>|>.*?</(?:\w+:)?CANopenObject>)", re.S)
PARAMETER = re.compile(r"<(?:\w+:)?parameter\b[^>]*?(?:/>|>.*?</(?:\w+:)?parameter>)", re.S)
UNIQUE_ID = re.compile(r'\buniqueID="([^"]*)"')
REF = re.compile(r'\buniqueIDRef="([^"]*)"')
TYPE_REF = re.compile(r'\bdataTypeIDRef="([^"]*)"')
DATA_TYPE = re.compile(r"<((?:\w+:)?(?:struct|array|enum|derived))\b[^>]*?(?:/>|>.*?</\1>)", re.S)


def shrink(text, keep):
    objects = OBJECT.findall(text)
    kept = objects[:keep]
    refs = {ref for obj in kept for ref in REF.findall(obj)}
    # Drop the objects after the first `keep`, then the parameters no kept object references.
    count = [0]

    def object_sub(match):
        count[0] += 1
        return match.group(0) if count[0] <= keep else ""

    text = OBJECT.sub(object_sub, text)

    def parameter_sub(match):
        ids = UNIQUE_ID.findall(match.group(0)[:200])
        return match.group(0) if ids and ids[0] in refs else ""

    text = PARAMETER.sub(parameter_sub, text)
    # Then the data types nothing left refers to (a struct may name another: keep those too).
    used = set(TYPE_REF.findall(DATA_TYPE.sub("", text)))
    for element in DATA_TYPE.finditer(text):
        ids = UNIQUE_ID.findall(element.group(0)[:300])
        if ids and ids[0] in used:
            used.update(TYPE_REF.findall(element.group(0)))

    def data_type_sub(match):
        ids = UNIQUE_ID.findall(match.group(0)[:300])
        return match.group(0) if not ids or ids[0] in used else ""

    text = DATA_TYPE.sub(data_type_sub, text)
    return re.sub(r"\n\s*\n", "\n", text)


def main():
    src, dst = sys.argv[1], sys.argv[2]
    limit = int(sys.argv[3]) if len(sys.argv) > 3 else 65536
    raw = open(src, "rb").read()
    if len(raw) <= limit:
        open(dst, "wb").write(raw)
        return
    text = raw.decode("utf-8", errors="replace")
    keep = 64
    while keep > 0:
        out = shrink(text, keep).encode("utf-8")
        if len(out) <= limit:
            open(dst, "wb").write(out)
            return
        keep //= 2
    open(dst, "wb").write(shrink(text, 1).encode("utf-8")[:limit])


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Writes firmware_protocol/golden_vectors.txt: byte-exact frames for every message of
firmware_protocol/gantry_messages.def, built independently of the C codec (the table is read
as text, fields packed with struct, the CRC from binascii.crc_hqx, which is CRC-16/CCITT-FALSE).
Both the host tests and the firmware tests decode and re-encode these frames.

Line format: NAME SEQUENCE field=value,field=value HEXBYTES"""
import binascii
import os
import re
import struct

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "firmware_protocol")
FORMATS = {"u8": "B", "u16": "H", "u32": "I", "i32": "i"}
RANGES = {"u8": (0, 255), "u16": (0, 65535), "u32": (0, 2**32 - 1), "i32": (-2**31, 2**31 - 1)}

table = open(os.path.join(HERE, "gantry_messages.def")).read()
table = re.sub(r"/\*.*?\*/", "", table, flags=re.S)
messages = re.findall(r"MESSAGE\((\w+),\s*(0x[0-9A-Fa-f]+),(.*?)\)\s*(?=MESSAGE|\Z)", table, re.S)

lines = ["# Golden frames of the gantry protocol; made by tools/make_golden_vectors.py, do not edit."]
for index, (name, ident, body) in enumerate(messages):
    fields = re.findall(r"FIELD\((\w+),\s*(\w+)\)", body)
    for variant in range(2):
        values = []
        for j, (ftype, fname) in enumerate(fields):
            lo, hi = RANGES[ftype]
            # Deterministic values that exercise every byte, the sign bit and the extremes.
            v = [(0x1234567 * (j + 3) + index * 977) % (hi - lo + 1) + lo, hi if j % 2 else lo][variant]
            values.append((ftype, fname, v))
        payload = b"".join(struct.pack("<" + FORMATS[t], v) for t, _, v in values)
        sequence = (index * 37 + variant * 101) % 256
        head = bytes([len(payload), sequence, int(ident, 16)]) + payload
        frame = bytes([0xA5]) + head + struct.pack("<H", binascii.crc_hqx(head, 0xFFFF))
        fields_text = ",".join(f"{n}={v}" for _, n, v in values)
        lines.append(f"{name} {sequence} {fields_text} {frame.hex()}")
open(os.path.join(HERE, "golden_vectors.txt"), "w").write("\n".join(lines) + "\n")
print(f"wrote {len(lines) - 1} frames")

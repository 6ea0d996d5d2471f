#!/usr/bin/env python3
"""Mutants of a saved map file, for map_cli_e2e.sh: for the header, every section of the file's
table, the table and the trailer, one byte flipped at the region's first, middle and last byte and
the file cut in the middle of the region; then the header with format version 2 and with another
vocabulary checksum, the header's and the whole file's checksums made right again so that only
the version or the vocabulary is wrong. Layout: core/io/map_file.h.

    mutate_map.py FILE OUT_DIR    writes OUT_DIR/<region>-<mutation>.alemap, prints one line each:
                                  <file> <what the refusal must say, an extended regex>
"""
import os
import struct
import sys

HEADER, TRAILER, ENTRY = 64, 32, 32
KINDS = {1: "meta", 2: "keyframes", 3: "landmarks"}


def fnv1a64(data):
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def main():
    src, out = sys.argv[1], sys.argv[2]
    data = open(src, "rb").read()
    if data[:8] != b"ALEMAP\r\n" or data[-32:-24] != b"ALEMAPND":
        sys.exit(f"mutate_map.py: {src} is not a map file")
    sections = struct.unpack_from("<I", data, 16)[0]
    table = struct.unpack_from("<Q", data, len(data) - TRAILER + 8)[0]
    regions = [("header", 0, HEADER)]
    for i in range(sections):
        kind, _, offset, size, _ = struct.unpack_from("<IIQQQ", data, table + ENTRY * i)
        regions.append((f"section{i}_{KINDS.get(kind, kind)}", offset, size))
    regions += [("table", table, ENTRY * sections), ("trailer", len(data) - TRAILER, TRAILER)]
    os.makedirs(out, exist_ok=True)

    def write(name, content, reason):
        path = os.path.join(out, name + ".alemap")
        with open(path, "wb") as f:
            f.write(content)
        print(path, reason)

    for name, offset, size in regions:
        if size <= 0:
            sys.exit(f"mutate_map.py: {name} is empty")
        for where, at in (("first", offset), ("middle", offset + size // 2), ("last", offset + size - 1)):
            b = bytearray(data)
            b[at] ^= 0x55
            write(f"{name}-flip_{where}", bytes(b), "refused: corrupt data")
        write(f"{name}-cut_middle", data[: offset + size // 2], "refused: corrupt data: .*(truncated|shorter than)")

    def with_header(field_offset, fmt, value):
        b = bytearray(data)
        struct.pack_into(fmt, b, field_offset, value)
        struct.pack_into("<Q", b, 56, fnv1a64(bytes(b[:56])))
        struct.pack_into("<Q", b, len(b) - TRAILER + 16, fnv1a64(bytes(b[: len(b) - TRAILER])))
        return bytes(b)

    write("header-version_2", with_header(8, "<I", 2), "refused: unsupported: .*format version 2, this build reads 1")
    vocabulary = struct.unpack_from("<Q", data, 32)[0]
    write("header-other_vocabulary", with_header(32, "<Q", vocabulary ^ 0x1234567890ABCDEF), "refused: .*vocabulary")


if __name__ == "__main__":
    main()

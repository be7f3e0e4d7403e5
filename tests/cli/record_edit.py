#!/usr/bin/env python3
"""Edits an ambdrop run record (an LCM event log) the way a hostile or broken writer would, for
the hostile_* CLI tests: cut it, overwrite an integer inside an event's payload, and recompute the
integrity checks so that the edit is not caught by them but by the reader's own bounds.

Usage: record_edit.py IN OUT OP...
  cut-after CHANNEL             drop everything after the last event on CHANNEL (its check, the
                                footer): what a recorder killed mid-run leaves
  i64 CHANNEL OFFSET VALUE      big-endian int64 at payload byte OFFSET of the last CHANNEL event
  i32 CHANNEL OFFSET VALUE      the same, int32
  f64 CHANNEL OFFSET VALUE      the same, IEEE double
  recheck                       recompute every AMBDROP_REC_CHECK over the events it covers
Payload offsets count the 8-byte LCM fingerprint.
"""
import struct
import sys

SYNC = 0xEDA1DA01
CHECK = "AMBDROP_REC_CHECK"
FNV_BASIS = 14695981039346656037
FNV_PRIME = 1099511628211


def read_events(path):
    data = open(path, "rb").read()
    events, pos = [], 0
    while pos + 28 <= len(data):
        sync, number, utime, clen, dlen = struct.unpack_from(">IqqII", data, pos)
        if sync != SYNC:
            raise SystemExit(f"{path}: no sync word at byte {pos}")
        pos += 28
        channel = data[pos:pos + clen].decode()
        pos += clen
        events.append([number, utime, channel, bytearray(data[pos:pos + dlen])])
        pos += dlen
    return events


def write_events(path, events):
    with open(path, "wb") as out:
        for number, utime, channel, payload in events:
            name = channel.encode()
            out.write(struct.pack(">IqqII", SYNC, number, utime, len(name), len(payload)))
            out.write(name)
            out.write(payload)


def fnv(data, h):
    for b in data:
        h = ((h ^ b) * FNV_PRIME) & 0xFFFFFFFFFFFFFFFF
    return h


def last_on(events, channel):
    for e in reversed(events):
        if e[2] == channel:
            return e
    raise SystemExit(f"no event on {channel}")


def recheck(events):
    h, count = FNV_BASIS, 0
    for e in events:
        if e[2] == CHECK:
            struct.pack_into(">qq", e[3], 16, count, struct.unpack(">q", struct.pack(">Q", h))[0])
            h, count = FNV_BASIS, 0
            continue
        h = fnv(e[2].encode(), h)
        h = fnv(e[3], h)
        count += 1


def main(argv):
    events = read_events(argv[1])
    ops = argv[3:]
    while ops:
        op = ops.pop(0)
        if op == "cut-after":
            last = events.index(last_on(events, ops.pop(0)))
            events = events[:last + 1]
        elif op in ("i64", "i32", "f64"):
            channel, offset, value = ops.pop(0), int(ops.pop(0)), ops.pop(0)
            fmt = {"i64": ">q", "i32": ">i", "f64": ">d"}[op]
            struct.pack_into(fmt, last_on(events, channel)[3], offset,
                             float(value) if op == "f64" else int(float(value)))
        elif op == "recheck":
            recheck(events)
        else:
            raise SystemExit(f"unknown op {op}")
    write_events(argv[2], events)


if __name__ == "__main__":
    main(sys.argv)

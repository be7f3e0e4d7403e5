#!/usr/bin/env bash
# The client kit's CAN files (`ambdrop can-export`) against the [can] table they come from, read
# here independently (Python's tomllib): every DBC signal has the table's identifier, start bit,
# length, byte order, sign, scale and offset; and a C program built with the generated header
# encodes values into exactly the bytes the table's layout gives (rounding ties to even,
# saturating) and decodes them back. The rig's table is varied to cover big-endian, 29-bit,
# unsigned and offset signals. Usage: can_export.sh AMBDROP_BINARY SOURCE_DIR
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
base="$source_dir/configs/jarroux2019_industrial_pid_can.toml"
cat >varied.toml <<TOML
base = "$base"

[can.sensors_out.de.x]
byte_order = "big"
offset_m = 1.5e-4

[can.sensors_out.nde.y]
id = 0x1ABCDE0
extended = true
signed = false
width_bytes = 4
byte_offset = 0
scale_m_per_count = 2.5e-8
offset_m = -5e-3
TOML
for config in "$base" varied.toml; do
  name=$(basename "$config" .toml)
  "$tool" can-export "$config" --header "$name.h" --dbc "$name.dbc" ||
    fail "can-export $config exited $?"
  python3 - "$config" "$name" <<'PY' || fail "$name: the generated files disagree with the table"
import re, struct, subprocess, sys, tomllib, pathlib
config, name = sys.argv[1], sys.argv[2]

def load(path):
    d = tomllib.loads(pathlib.Path(path).read_text())
    if "base" in d:
        parent = load(pathlib.Path(path).parent / d["base"])
        def merge(a, b):
            for k, v in b.items():
                a[k] = merge(a.get(k, {}), v) if isinstance(v, dict) else v
            return a
        return merge(parent, d)
    return d

can = load(config)["can"]
order0 = can.get("byte_order", "little")
signals = []  # (path, table, scale key, offset key)
for group, scale_key, offset_key in (("currents_in", "scale_A_per_count", "offset_A"),
                                     ("sensors_out", "scale_m_per_count", "offset_m")):
    for item, axes in can.get(group, {}).items():
        for axis, t in axes.items():
            signals.append((f"{group}.{item}.{axis}", t, t[scale_key], t.get(offset_key, 0.0)))
for item, t in can.get("status_out", {}).items():
    signals.append((f"status_out.{item}", t, t.get("scale_rad_s_per_count", 1.0),
                    t.get("offset_rad_s", 0.0)))

# DBC: every signal where the table puts it.
dbc = pathlib.Path(f"{name}.dbc").read_text()
found, message = {}, None
for line in dbc.splitlines():
    m = re.match(r"BO_ (\d+) ", line)
    if m:
        message = int(m.group(1))
    m = re.match(r" SG_ (\w+) : (\d+)\|(\d+)@([01])([+-]) \(([^,]+),([^)]+)\)", line)
    if m:
        found[m.group(1)] = (message, int(m.group(2)), int(m.group(3)), m.group(4), m.group(5),
                             float(m.group(6)), float(m.group(7)))
for path, t, scale, offset in signals:
    big = t.get("byte_order", order0) == "big"
    width = t["width_bytes"]
    start = 8 * t["byte_offset"] + (7 if big else 0)
    ident = t["id"] | (0x80000000 if t.get("extended", False) else 0)
    want = (ident, start, 8 * width, "0" if big else "1", "-" if t.get("signed", False) else "+",
            scale, offset)
    got = found.get(path.replace(".", "_"))
    assert got == want, (path, got, want)
trigger = [l for l in dbc.splitlines() if l.startswith("VAL_ 128 trigger_in")]
assert trigger and '1 "power_fail"' in trigger[0] and '2 "power_restore"' in trigger[0], trigger

# The header: a C program encodes and decodes every signal at a few values.
values = [0.0, 1e-3, -2.5e-3, 0.0123456, -7.77, 1e9, -1e9, 3.5]
def raw_of(v, scale, offset, width, signed):
    lo, hi = (-(1 << (8 * width - 1)), (1 << (8 * width - 1)) - 1) if signed else (0, (1 << (8 * width)) - 1)
    return min(max(round((v - offset) / scale), lo), hi)  # round(): ties to even
lines = ['#include <stdio.h>', f'#include "{name}.h"', 'int main(void) {', '  uint8_t d[64];']
expected = []
for path, t, scale, offset in signals:
    macro = "AMBDROP_CAN_" + re.sub(r"[^A-Za-z0-9]", "_", path).upper()
    width, signed = t["width_bytes"], t.get("signed", False)
    big = t.get("byte_order", order0) == "big"
    for v in values:
        lines.append("  for (int i = 0; i < 64; ++i) d[i] = 0;")
        lines.append(f"  AMBDROP_CAN_SET(d, {macro}, {v!r});")
        lines.append(f'  printf("%s", "{path} ");')
        lines.append(f'  for (int i = 0; i < {t["byte_offset"] + width}; ++i) printf("%02x", d[i]);')
        lines.append(f'  printf(" %.17g\\n", AMBDROP_CAN_GET(d, {macro}));')
        raw = raw_of(v, scale, offset, width, signed)
        fmt = (">" if big else "<") + {1: "b", 2: "h", 4: "i"}[width]
        if not signed:
            fmt = fmt.upper()
        payload = bytes(t["byte_offset"]) + struct.pack(fmt, raw)
        expected.append((path, payload.hex(), raw * scale + offset))
lines += ["  return 0;", "}"]
pathlib.Path(f"{name}_roundtrip.c").write_text("\n".join(lines) + "\n")
subprocess.run(["cc", "-std=c99", "-Wall", "-Werror", "-o", f"{name}_roundtrip",
                f"{name}_roundtrip.c", "-lm"], check=True)
out = subprocess.run([f"./{name}_roundtrip"], check=True, capture_output=True, text=True).stdout
rows = out.splitlines()
assert len(rows) == len(expected), (len(rows), len(expected))
for row, (path, payload, physical) in zip(rows, expected):
    p, data, back = row.split()
    assert (p, data) == (path, payload), (row, payload)
    assert float(back) == physical, (row, physical)
print(f"{name}: {len(found)} DBC signals and {len(rows)} header encodings agree with the table")
PY
done
# No [can] table: a clear error, exit 2.
rc=0
"$tool" can-export "$source_dir/configs/jarroux2019_industrial_pid.toml" --dbc x.dbc 2>err.txt || rc=$?
[[ $rc == 2 ]] && grep -q "no \[can\] table" err.txt || fail "no [can]: exit $rc, $(cat err.txt)"
echo "can-export: ok"

#!/usr/bin/env python3
"""Golden trajectories: every rig in configs/ and every scenario in configs/scenarios/, run by the
`ambdrop` binary as a user runs them, must give the stored trajectory hash (summary.json's
`trajectory_hash`: every bit of the state at each output step and of every sensor sample).
A refactor that claims to be bit-neutral proves it here.

`ambdrop validate` is covered too (its stepped drops and phase spreads are loops of their own):
its hash is taken over every check's full-precision deviation and printed value.

Each rig is also recorded and replayed: `ambdrop replay` must reproduce the run it recorded bit for
bit, so its hash must equal the live run's.

Usage:
  golden_hashes.py AMBDROP SOURCE_DIR            check against tests/determinism/golden_hashes.txt
  golden_hashes.py AMBDROP SOURCE_DIR --update   rewrite that file (commit it on its own, saying
                                                 why the results changed)
  ... [--only SUBSTRING] [--kinds sim,replay,scenario,validate] [--jobs N]
Exit 0 when every hash matches, 1 otherwise (each difference is printed).
"""
import argparse
import concurrent.futures
import hashlib
import json
import os
import pathlib
import subprocess
import sys
import tempfile

GOLDEN = pathlib.Path(__file__).with_name("golden_hashes.txt")


def runs(source_dir: pathlib.Path):
    """(kind, config path relative to the source dir) for every run the file covers."""
    configs = sorted((source_dir / "configs").glob("*.toml"))
    scenarios = sorted((source_dir / "configs" / "scenarios").glob("*.toml"))
    for c in configs:
        yield ("sim", c.relative_to(source_dir).as_posix())
    for c in configs:
        yield ("replay", c.relative_to(source_dir).as_posix())
    for s in scenarios:
        yield ("scenario", s.relative_to(source_dir).as_posix())
    yield ("validate", "configs")


def run_one(tool: str, source_dir: pathlib.Path, kind: str, config: str, work: pathlib.Path):
    """Returns (key, hash, detail, error)."""
    key = f"{kind} {config}"
    out = work / key.replace("/", "_").replace(" ", "_")
    path = str(source_dir / config)
    if kind == "validate":
        proc = subprocess.run([tool, "validate", "--configs", path, "--out", str(out),
                               "--allow-known-failures", "-q"], capture_output=True, text=True)
        report = out / "validate.json"
        if not report.exists():
            return key, None, None, f"exited {proc.returncode} with no validate.json: {proc.stderr}"
        checks = json.loads(report.read_text())
        text = json.dumps([[c.get("case"), c.get("quantity"), c.get("ambdrop"),
                            repr(c.get("deviation"))] for c in checks])
        value = hashlib.sha256(text.encode()).hexdigest()[:16]
        passed = sum(1 for c in checks if c.get("pass"))
        return key, value, f"checks={len(checks)} pass={passed} exit={proc.returncode}", None
    if kind == "sim":
        cmd = [tool, "sim", path, "--out", str(out), "--quiet"]
    elif kind == "scenario":
        cmd = [tool, "sim", "--scenario", path, "--out", str(out), "--quiet"]
    else:
        record = out.with_suffix(".lcm")
        rec = subprocess.run(
            [tool, "sim", path, "--out", str(out) + "_live", "--quiet", "--record", str(record)],
            capture_output=True, text=True)
        if rec.returncode != 0:
            return key, None, None, f"recording exited {rec.returncode}: {rec.stderr.strip()}"
        live = json.loads((pathlib.Path(str(out) + "_live") / "summary.json").read_text())
        cmd = [tool, "replay", str(record), "--out", str(out), "--quiet"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    summary_path = out / "summary.json"
    if not summary_path.exists():
        return key, None, None, f"exited {proc.returncode} with no summary.json: {proc.stderr.strip()}"
    summary = json.loads(summary_path.read_text())
    value = summary.get("trajectory_hash")
    if not value:
        return key, None, None, "summary.json has no trajectory_hash"
    detail = f"steps={summary.get('steps')} status={summary.get('status')}"
    # A scenario whose expectation fails exits 4; that is a result, and its hash still counts.
    if proc.returncode not in (0, 4) or summary.get("status") not in ("ok", "watchdog_stop"):
        detail += f" exit={proc.returncode}"
    if kind == "replay" and value != live.get("trajectory_hash"):
        return key, value, detail, (f"replay {value} differs from the live run it recorded "
                                    f"{live.get('trajectory_hash')}")
    return key, value, detail, None


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("tool")
    parser.add_argument("source_dir", type=pathlib.Path)
    parser.add_argument("--update", action="store_true")
    parser.add_argument("--only", default="")
    # The sanitizer build checks the trajectories' independence of the optimisation level on the
    # live runs alone: the replays and `validate` repeat the same loops (Release checks them).
    parser.add_argument("--kinds", default="sim,replay,scenario,validate")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args()

    kinds = set(args.kinds.split(","))
    todo = [r for r in runs(args.source_dir)
            if args.only in f"{r[0]} {r[1]}" and r[0] in kinds]
    stored = {}
    if GOLDEN.exists():
        for line in GOLDEN.read_text().splitlines():
            if line.startswith("#") or not line.strip():
                continue
            kind, config, value, *detail = line.split()
            stored[f"{kind} {config}"] = (value, " ".join(detail))

    results = {}
    with tempfile.TemporaryDirectory(prefix="ambdrop_golden_") as work:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            futures = [pool.submit(run_one, args.tool, args.source_dir, k, c, pathlib.Path(work))
                       for k, c in todo]
            for f in futures:
                key, value, detail, error = f.result()
                results[key] = (value, detail, error)

    failures = 0
    matched = 0
    for key, (value, detail, error) in results.items():
        if error:
            print(f"FAIL {key}: {error}")
            failures += 1
            continue
        if args.update:
            print(f"{key} {value} {detail}")
            continue
        if key not in stored:
            print(f"FAIL {key}: no stored hash (run with --update and commit the file)")
            failures += 1
        elif stored[key][0] != value:
            print(f"FAIL {key}: {value} ({detail}), stored {stored[key][0]} ({stored[key][1]})")
            failures += 1
        else:
            print(f"ok   {key} {value} {detail}")
            matched += 1

    if args.update:
        if failures:
            print(f"{failures} runs failed: {GOLDEN.name} not written", file=sys.stderr)
            return 1
        merged = {k: (v[0], v[1]) for k, v in stored.items()}
        merged.update({k: (v[0], v[1]) for k, v in results.items()})
        lines = ["# Golden trajectory hashes (tests/determinism/golden_hashes.py --update writes",
                 "# this file): kind, config, summary.json's trajectory_hash, steps and status."]
        known = {f"{k} {c}" for k, c in runs(args.source_dir)}
        lines += [f"{k} {v} {d}" for k, (v, d) in sorted(merged.items()) if k in known]
        GOLDEN.write_text("\n".join(lines) + "\n")
        print(f"wrote {GOLDEN} ({len(lines) - 2} runs)")
        return 0
    if not args.only and kinds == {"sim", "replay", "scenario", "validate"}:
        missing = set(stored) - set(results)
        for key in sorted(missing):
            print(f"FAIL {key}: stored, but its config is gone (run --update)")
            failures += 1
    print(f"{matched} of {len(results)} runs match their golden hash"
          + (f"; {failures} failed" if failures else ""))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

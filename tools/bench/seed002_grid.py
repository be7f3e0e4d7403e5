#!/usr/bin/env python3
# The grid behind seed 002's known failure (tools/validation/seed002_cases.cpp): the unpublished
# friction, race spin inertia, ball damping, contact length and slip definition of
# configs/chen_itri_flexible.toml, each set dropped at 18 000, 14 000 and 10 000 rpm and 8
# unbalance phases (as the validation case does), the medians held against the paper's peaks.
# One line per set: how many of the six peaks are within 25 %, whether both fall with the
# speed, the largest excursion over the clearance and the medians (kN, front / rear).
#
#   tools/bench/seed002_grid.py [BUILD_DIR=build]      (about 20 min on 2 cores)
import itertools
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
AMBDROP = os.path.join(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"),
                       "tools", "ambdrop")
CONFIG = os.path.join(ROOT, "configs", "chen_itri_flexible.toml")
PUBLISHED_N = {18000: (2.3e4, 2.35e4), 14000: (2.25e4, 2.15e4), 10000: (2.1e4, 1.9e4)}
PHASES = 8


def both(key, value):
    return [f"tdb.{t}.{key}={value}" for t in ("front", "rear")]


def drop(work, rpm, phase, overrides):
    out = os.path.join(work, f"{rpm}_{phase}")
    cmd = [AMBDROP, "sim", CONFIG, "--out", out, "-q",
           "--set", "simulation.duration_s=0.21",
           "--set", f"simulation.spin_speed_rad_s={rpm * math.pi / 30!r}",
           "--set", f"unbalance.rotor.phase_rad={2 * math.pi * phase / PHASES!r}"]
    for o in overrides:
        cmd += ["--set", o]
    subprocess.run(cmd, check=True)
    with open(os.path.join(out, "summary.json")) as f:
        tdbs = json.load(f)["tdbs"]
    return ([tdbs[t]["peak_normal_force_N"] for t in ("front", "rear")],
            max(tdbs[t]["max_excursion_over_clearance"] for t in ("front", "rear")))


def main():
    grid = itertools.product(["contact_point", "spin_only"], [(0.25, 0.35), (0.3, 0.4), (0.4, 0.5)],
                             [1e-4, 1.5e-4, 2e-4, 3e-4], [1320, 3300], [0.013, 0.0065])
    for slip, (mu_d, mu_s), inertia, cb, length in grid:
        overrides = (both("ball_bearing_tdb.friction.slip_speeds", f'"{slip}"') +
                     both("ball_bearing_tdb.friction.kinetic_coefficient", mu_d) +
                     both("ball_bearing_tdb.friction.static_coefficient", mu_s) +
                     both("spin.inertia_kg_m2", inertia) +
                     both("ball_bearing_tdb.bearing.damping_N_s_per_m", cb) +
                     both("ball_bearing_tdb.line_contact.length_m", length))
        jobs = [(rpm, k) for rpm in PUBLISHED_N for k in range(PHASES)]
        with tempfile.TemporaryDirectory() as work, ThreadPoolExecutor(2) as pool:
            runs = list(pool.map(lambda j: drop(work, j[0], j[1], overrides), jobs))
        peaks = {rpm: [] for rpm in PUBLISHED_N}
        excursion = 0.0
        for (rpm, _), (p, x) in zip(jobs, runs):
            peaks[rpm].append(p)
            excursion = max(excursion, x)
        med = {rpm: [statistics.median(p[i] for p in peaks[rpm]) for i in (0, 1)]
               for rpm in PUBLISHED_N}
        within = sum(abs(med[r][i] / PUBLISHED_N[r][i] - 1) <= 0.25
                     for r in PUBLISHED_N for i in (0, 1))
        falling = sum(med[18000][i] > med[14000][i] > med[10000][i] for i in (0, 1))
        print(f"{slip} mu {mu_d} J {inertia:g} Cb {cb} L {length}: peaks within 25 % {within}/6,"
              f" falling {falling}/2, excursion {excursion:.2f} | " +
              " ".join(f"{r // 1000}k {med[r][0] / 1e3:.1f}/{med[r][1] / 1e3:.1f}"
                       for r in PUBLISHED_N), flush=True)


if __name__ == "__main__":
    main()

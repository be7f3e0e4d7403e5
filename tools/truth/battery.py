#!/usr/bin/env python3
"""The scoring battery of `ambdrop fit` on independent records (issues 15 and 23).

A benchmark, not a test: it makes every record of `ambdrop_truth --battery`, runs `ambdrop fit`
on each blind copy, reads the record's truth.json and scores the fit by the issues' table. It
exits 0 whatever the score; non-zero only when a fit or the generator fails or a file is missing.

    battery.py AMBDROP AMBDROP_TRUTH RIG.json CONFIG.toml OUT
               [--declared [--count N]] [--jobs N] [--only NAME ...]
               [--record-file record.csv] [--markdown FILE] [--score-only] [--fit-arg ARG ...]
               [--ceiling] [--clean-seeds N [--first-seed S]] [--battery-seed S]

    AMBDROP, AMBDROP_TRUTH  the two binaries (build/ambdrop, build/tools/truth/ambdrop_truth)
    RIG.json, CONFIG.toml   the generator's rig and its translation into an ambdrop config
                            (tools/truth/rigs/rigid_rotor_a.json, tests/truth/rigid_rotor_a.toml)
    OUT                     OUT/records (the battery), OUT/fits/<record>/ (fit.json, fit.log)
    --declared              issue 23's battery instead of the 16 kinds: the two clean records
                            and --count (default 12) declared_off records, one number of the rig
                            sheet off in each (`ambdrop_truth --battery-declared`)
    --jobs N                fits run at once (default 1; each fit already uses 2 threads)
    --only NAME             only the records whose effect kind, record name or declared_off
                            entry (`tdbs.de.clearance_m`) is NAME (repeat)
    --record-file F         which file of each blind record goes to `--measured` (default
                            record.csv, as the generator writes it: time in ms, um, rpm; the
                            config's [measurement] names its time column and units.
                            record_si.csv is the same in SI with a `t` column)
    --markdown FILE         the table also as markdown
    --score-only            neither generate nor fit: score the fit.json files already in OUT
    --fit-arg ARG           passed on to `ambdrop fit` (repeat; e.g. --fit-arg=--threads=1)
    --clean-seeds N         instead of the battery: N clean records of the rig, seeds S to
                            S+N-1 (--first-seed, default 3: the battery's own are 1 and 2), each
                            `ambdrop_truth --effect clean --seed`; the count is then the rate of
                            invented effects on records of the rig as declared
    --battery-seed S        the battery's (or --declared's) records from seed S on instead of 1
                            (101): the same kinds at other sizes and jitters, records no rule
                            of the fit was made on (`ambdrop_truth --first-seed`)
    --ceiling               also fit each record with its truth's own `--set` lines
                            (OUT/fits/<record>/ceiling/): the residual the true numbers leave
                            on the part the record's fit judged, so the cut the record can show
                            at best (column "ceiling"); a second count takes only the records
                            whose ceiling reaches the 3x cut, with the clean and outside ones

Standard library only. See tools/truth/README.md ("Scoring battery") and docs/verification.md.
"""

import argparse
import concurrent.futures
import json
import math
import os
import subprocess
import sys
import time
import tomllib
from pathlib import Path

# ---------------------------------------------------------------------------------------------
# Scoring rules (issue 15 "How it is checked", issue 23 "How it is checked"). All in this block.
#
# A record is right (HIT) when:
#   - clean (the truth sets no key, effect "clean"): verdict `no_effect_needed`. An effect chosen
#     on a clean record is "invented".
#   - outside the library (the truth sets no key and is not clean, e.g. side_pull): verdict
#     `unexplained`.
#   - otherwise, all of:
#     1. name: the first chosen effect's `set` lines touch a key group of the truth, and every
#        key group of the truth is touched by a chosen effect's `set` lines or by an effect listed
#        in `equivalent` (a look-alike or a pair counts when both are listed); where the first
#        chosen touches none, a look-alike listed beside it (fit.json schema 2, with its set
#        lines) that touches one names the truth (issue 23: "a look-alike pair counts as right
#        when both are listed as equivalent"), and its values are the ones compared;
#     2. value: every numeric key that the truth and a chosen effect both set is within 20 % of
#        the true change from the declared value (VALUE_TOLERANCE); angles within 0.35 rad;
#        zero-valued changes within ABSOLUTE_TOLERANCE;
#     3. cut: the residual above the noise floor of the part the verdict judges falls at least
#        3x (>= MIN_CUT): fit.json's `judged_on` names it, the whole record, the drop's start
#        (where the start departs; after the first impacts this rig's drop is chaotic, and its
#        clean records leave 0.05 over the whole record, ten times the noise), the start's
#        departing sensors (`sensors`), the speeds or the levitated time before the trigger;
#        older fit.json
#        files without it: rms_before.overall_above_noise / rms_after.overall_above_noise.
#   A value the fit itself reports as not decided by the record (fit.json `"decided": false`)
#   is marked "(open)" and still held to the rule; a record right but for such values is
#   counted apart ("more right but for values the fit calls open"), never as right.
#
# MAPPING RULE (truth keys <-> fit effects), the one place it is written down:
#   - A key is its `--set` path. Keys are compared after `normalise_key`: an unbalance table's
#     own name is not physics, so `unbalance.<name>.<leaf>` becomes `unbalance.static.<leaf>`
#     when the lines set one unbalance table and `unbalance.couple_<k>.<leaf>` (k = 1, 2, ... by
#     position_m) when they set several (the generator's hidden_static / hidden_couple_a,b and the
#     fit's fitted / fitted_couple_a,b).
#   - A key group is a key's table (the path without its last segment, normalised). Switch
#     keys (SWITCH_LEAVES: `enabled`, `current_law`, `model`, ...) do not make a touch by
#     themselves; a touch is a shared non-switch key.
#   - A chosen effect's keys are its `set` lines in fit.json. An `equivalent` entry carries its
#     own `set` lines too (fit.json schema 2); in an older fit.json it is a name only, and its
#     keys come from EFFECT_NAME_KEYS (the fit's effect library, tools/fit/effect_library.cpp):
#     family, then ":item" for one TDB / AMB / sensor, no item for every one of them.
#   - Values: a key's declared value is what `ambdrop keys CONFIG --json` reads (a key it does
#     not list, e.g. `controller.delay_samples`, is read from the TOML and its `base =` chain),
#     unless the truth switches its table on (`<table>.enabled=true`) and the config has it
#     off: then the declared value is "none" and the change is the whole truth value.
#   - An `equivalent` or chosen effect named by a key path (`tdb.de.clearance_m`, or
#     `tdb.*.clearance_m` for the same key on every item) writes that key (on every item).
#
# DECLARED_OFF (issue 23, `--declared`): the truth is one `--set` line, KEY=TRUE, one number of
# the rig sheet off (truth.json "entry"). A declared_off record is right (HIT) when:
#   a. name: the first chosen effect's `set` lines set KEY itself (a group effect that sets the
#      same key on every item counts when its lines include KEY); or else an effect listed in
#      `equivalent` sets KEY (schema 2: its `set` lines; older fit.json: its name's keys);
#   b. value: the value that effect's line sets for KEY is within VALUE_TOLERANCE (20 %) of the
#      true change from the declared value; a number declared 0 (a sensor offset) is held to
#      its ABSOLUTE_TOLERANCE instead (1 um for an offset); no value (an old fit.json's bare
#      name) is a miss;
#   c. cut: as rule 3 above, at least MIN_CUT (whichever effect named KEY).
#   Clean records of that battery: as above, right only with `no_effect_needed`.
MIN_CUT = 3.0
VALUE_TOLERANCE = 0.2  # of the true change from the declared value
ANGLE_TOLERANCE_RAD = 0.35
# Absolute tolerances where the true change is zero (or below the tolerance), by key leaf.
ABSOLUTE_TOLERANCE = {
    "delay_s": None,  # half a controller period (the fit delays in whole samples); see below
    "eccentricity_m": 1e-6,  # kg m with a unit mass
    "x_m": 1e-6,
    "y_m": 1e-6,
    "offset_m": 1e-6,
    "offset_x_m": 1e-6,
    "offset_y_m": 1e-6,
    "clearance_m": 1e-6,
    "drag_torque_N_m": 1e-4,
    "time_constant_s": 1e-4,
    "hold_time_s": 1e-4,
    "coefficient": 0.01,
    "gain": 0.01,
    "gain_x": 0.01,
    "gain_y": 0.01,
    "cutoff_Hz": 100.0,
}
DEFAULT_ABSOLUTE_TOLERANCE = 1e-9
SWITCH_LEAVES = {"enabled", "current_law", "model", "ribbon", "law"}
# Keys that place an effect rather than size it: not compared as values. The Dahl law's form
# (beta and the hardening envelopes' a, b, c, d; the threshold's scale) is the fit's own, tied to
# the three numbers it fits (tools/fit/effect_library.cpp, RibbonDryFriction): its slipping
# threshold and slipping stiffness are compared, the form as little as a sign's regularisation.
# The mass a ribbon carries (outer_race_mass_kg) is the candidate's assumption where the rig
# declares none, the race's own (a thin ring's, from its inertia), not a fitted number: the
# drop's start does not decide it (rigid_hc_g's Dahl record of seed 13: 0.158 or 0.3 kg, both at
# the noise).
NOT_COMPARED_LEAVES = SWITCH_LEAVES | {"position_m", "mass_kg", "beta_per_m", "threshold_scale",
                                       "outer_race_mass_kg",
                                       "upper_hardening_N", "upper_hardening_rate_per_m",
                                       "lower_hardening_N", "lower_hardening_rate_per_m"}

# A fit parameter -> the leaf of the key it sets, where the two differ (fit.json names the
# parameter; the truth names the key).
KEY_OF_PARAMETER = {"filter_time_constant_s": "cutoff_Hz"}

# The fit's effect names -> the --set key patterns they write ("*" = every item).
EFFECT_NAME_KEYS = {
    "tdb_misalignment": ["tdb.{}.misalignment.x_m", "tdb.{}.misalignment.y_m"],
    "tdb_clearance": ["tdb.{}.clearance_m"],
    "friction_coefficient": ["tdb.{}.friction.coefficient",
                             "tdb.{}.ball_bearing_tdb.friction.kinetic_coefficient"],
    "unbalance": ["unbalance.static.eccentricity_m", "unbalance.static.phase_rad"],
    "couple_unbalance": ["unbalance.couple_1.eccentricity_m", "unbalance.couple_1.phase_rad",
                         "unbalance.couple_2.eccentricity_m", "unbalance.couple_2.phase_rad"],
    "amb_flux_decay": ["amb.{}.flux_decay.time_constant_s"],
    "sensor_runout": ["sensor.{}.runout.amplitude_1x_m", "sensor.{}.runout.phase_1x_rad"],
    "sensor_runout_2x": ["sensor.{}.runout.amplitude_2x_m", "sensor.{}.runout.phase_2x_rad"],
    "sensor_gain_offset": ["sensor.{}.gain", "sensor.{}.offset_m"],
    "sensor_lag": ["sensor.{}.lag.delay_s", "sensor.{}.lag.cutoff_Hz"],
    "tdb_drag_torque": ["tdb.{}.spin.drag_torque_N_m"],
    "ribbon_dry_friction": ["tdb.{}.four_dof.dahl.slipping_threshold_N",
                            "tdb.{}.contact_law.dahl.slipping_threshold_N"],
    "ribbon_cross_coupling": ["tdb.{}.four_dof.cross_coupled.cross_coupling",
                              "tdb.{}.contact_law.cross_coupled.cross_coupling"],
}
# ---------------------------------------------------------------------------------------------


class BatteryError(Exception):
    """A fit or the generator failed, or a file is missing: the run exits non-zero."""


def split_line(line):
    key, _, value = line.partition("=")
    return key.strip(), value.strip()


def normalise_keys(pairs):
    """[(key, value)] -> [(normalised key, value)] by the mapping rule above."""
    tables = {}
    for key, value in pairs:
        parts = key.split(".")
        if parts[0] == "unbalance" and len(parts) >= 3:
            t = tables.setdefault(parts[1], {"position": math.inf})
            if parts[-1] == "position_m":
                t["position"] = as_number(value, math.inf)
    if len(tables) == 1:
        rename = {name: "static" for name in tables}
    else:
        order = sorted(tables, key=lambda n: (tables[n]["position"], n))
        rename = {name: f"couple_{k + 1}" for k, name in enumerate(order)}
    out = []
    for key, value in pairs:
        parts = key.split(".")
        if parts[0] == "unbalance" and len(parts) >= 3:
            parts[1] = rename[parts[1]]
        out.append((".".join(parts), value))
    return out


def as_number(text, default=None):
    try:
        return float(text)
    except (TypeError, ValueError):
        return default


def leaf(key):
    return key.rsplit(".", 1)[-1]


def group(key):
    return key.rsplit(".", 1)[0]


def effect_name_keys(name, items):
    """The key paths an effect of the fit's library writes, from its name alone."""
    if "." in name and ":" not in name:  # named by its key path; "*" for every item
        parts = name.split(".")
        if len(parts) >= 3 and parts[1] == "*":
            return [".".join([parts[0], i] + parts[2:]) for i in items]
        return [name]
    family, _, item = name.partition(":")
    patterns = EFFECT_NAME_KEYS.get(family, [])
    keys = []
    for p in patterns:
        if "{}" not in p:
            keys.append(p)
        elif item:
            keys.append(p.format(item))
        else:
            keys.extend(p.format(i) for i in items)
    return keys  # already in normalised form (EFFECT_NAME_KEYS names the unbalance tables so)


def touched_groups(keys, truth_groups):
    """The truth's key groups that non-switch keys in `keys` touch."""
    hit = set()
    for k in keys:
        if leaf(k) in SWITCH_LEAVES:
            continue
        for g, members in truth_groups.items():
            if k in members:
                hit.add(g)
    return hit


def wrap_angle(a):
    return math.remainder(a, 2.0 * math.pi)


def absolute_tolerance(key, controller_period_s):
    lf = leaf(key)
    if lf == "delay_s":
        return 0.5 * controller_period_s
    return ABSOLUTE_TOLERANCE.get(lf, DEFAULT_ABSOLUTE_TOLERANCE)


def short(key):
    """A key's table and leaf (`de.clearance_m`, `misalignment.x_m`) for the table."""
    return ".".join(key.split(".")[-2:])


def compare_value(key, fitted, true, declared, controller_period_s):
    """(ok, text) for one key: the fitted value against the truth's change from declared."""
    if leaf(key).endswith("_rad"):
        err = abs(wrap_angle(fitted - true))
        return err <= ANGLE_TOLERANCE_RAD, f"{short(key)} {fitted:.3g} vs {true:.3g}"
    change = true - (declared if declared is not None else 0.0)
    tol_abs = absolute_tolerance(key, controller_period_s)
    if abs(change) > tol_abs:
        ok = abs(fitted - true) <= VALUE_TOLERANCE * abs(change)
        pct = 100.0 * (fitted - true) / abs(change)
        text = f"{short(key)} {fitted:.4g} vs {true:.4g} ({pct:+.0f} % of change)"
    else:
        ok = abs(fitted - true) <= tol_abs
        text = f"{short(key)} {fitted:.3g} vs {true:.3g} (abs tol {tol_abs:.2g})"
    return ok, text


class Declared:
    """The config's keys as `ambdrop keys --json` reads them."""

    def __init__(self, ambdrop, config):
        out = subprocess.run([ambdrop, "keys", config, "--json"], capture_output=True, text=True)
        if out.returncode != 0:
            raise BatteryError(f"ambdrop keys {config} failed ({out.returncode}): {out.stderr}")
        self.values = {k["path"]: k["value"] for k in json.loads(out.stdout)["keys"]}
        self.tdbs = sorted({p.split(".")[1] for p in self.values if p.startswith("tdb.")})
        self.ambs = sorted({p.split(".")[1] for p in self.values if p.startswith("amb.")})
        self.sensors = sorted({p.split(".")[1] for p in self.values if p.startswith("sensor.")})
        rate = self.values.get("controller.rate_Hz")
        self.controller_period_s = 1.0 / rate if rate else 1e-4
        # `keys` lists numbers only: the switches come from the TOML (and its `base =` chain).
        self.toml = []
        path = Path(config)
        while path is not None and len(self.toml) < 8:
            with open(path, "rb") as f:
                doc = tomllib.load(f)
            self.toml.append(doc)
            base = doc.get("base")
            path = (path.parent / base) if isinstance(base, str) else None

    def switched_on(self, table):
        """Whether the config declares `<table>.enabled = true` (the nearest file wins)."""
        for doc in self.toml:
            node = doc
            for part in table.split("."):
                node = node.get(part) if isinstance(node, dict) else None
            if isinstance(node, dict) and "enabled" in node:
                return node["enabled"] is True
        return False

    def items(self, family):
        if family == "sensor" or family.startswith("sensor_"):
            return self.sensors
        if family.startswith("amb"):
            return self.ambs
        if family.startswith("sensor"):
            return self.sensors
        return self.tdbs

    def toml_value(self, key):
        """A number the TOML chain declares (for keys `ambdrop keys` does not list), or None."""
        for doc in self.toml:
            node = doc
            for part in key.split("."):
                name, _, index = part.partition("[")
                node = node.get(name) if isinstance(node, dict) else None
                if index and isinstance(node, list):
                    k = int(index.rstrip("]"))
                    node = node[k] if k < len(node) else None
            if isinstance(node, (int, float)) and not isinstance(node, bool):
                return float(node)
        return None

    def value(self, key, truth_keys):
        """The declared value of a truth key, None when the truth switches its table on."""
        table = group(key)
        if truth_keys.get(table + ".enabled") == "true" and not self.switched_on(table):
            return None
        v = self.values.get(key)
        return v if v is not None else self.toml_value(key)


def equivalent_names(fit):
    """The look-alikes' names: schema 2 lists objects, older fit.json names."""
    return [e["effect"] if isinstance(e, dict) else e for e in fit.get("equivalent", [])]


def score_declared_off(row, truth, fit, declared):
    """Fills `row` for a declared_off truth by the DECLARED_OFF rules above."""
    row["invented"] = False
    lines = [split_line(x) for x in truth.get("ambdrop_set", [])]
    if len(lines) != 1:
        raise BatteryError(f"{row['record']}: a declared_off truth sets one key, found {lines}")
    key, true_text = lines[0]
    true_value = as_number(true_text)
    notes = []
    named_by, fitted = None, None
    if fit["chosen"]:
        first = dict(split_line(x) for x in fit["chosen"][0]["set"])
        if key in first:
            named_by, fitted = fit["chosen"][0]["effect"], first[key]
    if named_by is None:
        for e in fit.get("equivalent", []):
            if isinstance(e, dict):
                lines_e = dict(split_line(x) for x in e["set"])
                if key in lines_e:
                    named_by, fitted = f"equivalent {e['effect']}", lines_e[key]
                    break
            elif key in effect_name_keys(e, declared.items(key.split(".")[0])):
                named_by, fitted = f"equivalent {e} (no value)", None
                break
    if named_by is None:
        if fit["chosen"]:
            notes.append(f"first chosen does not set {key}, nor does an equivalent")
        else:
            notes.append(f"nothing chosen ({fit['verdict']}), no equivalent sets {key}")
    values_ok = False
    if named_by is not None:
        f = as_number(fitted)
        if f is None or true_value is None:
            notes.append(f"{named_by}: no value for {key}")
        else:
            d = declared.value(key, {})
            if d == 0.0:  # declared zero: the absolute tolerance, not 20 % of the change
                tol = absolute_tolerance(key, declared.controller_period_s)
                values_ok = abs(f - true_value) <= tol
                text = f"{short(key)} {f:.4g} vs {true_value:.4g} (abs tol {tol:.2g})"
            else:
                values_ok, text = compare_value(key, f, true_value, d,
                                                declared.controller_period_s)
            row["value"] = text + ("" if values_ok else " !")
            by_first = bool(fit["chosen"]) and named_by == fit["chosen"][0]["effect"]
            if not by_first:
                row["value"] += f" [{named_by}]"
            if not values_ok:
                notes.append("value off")
    cut_ok = row["cut"] >= MIN_CUT
    if not cut_ok:
        notes.append(f"cut {row['cut']:.3g}x < {MIN_CUT:g}x")
    row["hit"] = named_by is not None and values_ok and cut_ok
    row["note"] = "; ".join(notes)
    return row


def score(record, truth, fit, declared):
    """One table row (a dict) for a record."""
    row = {
        "record": record,
        "truth": truth["effect"],
        "description": truth.get("description", ""),
        "verdict": fit["verdict"],
        "chosen": ", ".join(c["effect"] for c in fit["chosen"]) or "-",
        "equivalent": ", ".join(equivalent_names(fit)),
        "value": "",
        "note": "",
    }
    part = fit.get(fit.get("judged_on", ""))
    if part:
        noise = part["noise_floor"]
        before = math.sqrt(max(0.0, part["rms_before"] ** 2 - noise ** 2))
        after = math.sqrt(max(0.0, part["rms_after"] ** 2 - noise ** 2))
    else:
        before = fit["rms_before"]["overall_above_noise"]
        after = fit["rms_after"]["overall_above_noise"]
    cut = math.inf if after <= 0.0 else before / after
    row["cut"] = cut
    row["rms"] = f"{fit['rms_before']['overall']:.3g}->{fit['rms_after']['overall']:.3g}"
    if truth["effect"] == "declared_off":
        row["truth"] = f"declared_off {truth.get('entry', '?')}"
        return score_declared_off(row, truth, fit, declared)
    raw = [split_line(s) for s in truth.get("ambdrop_set", [])]
    if not raw:
        if truth["effect"] == "clean":
            row["hit"] = fit["verdict"] == "no_effect_needed"
            row["invented"] = bool(fit["chosen"])
            row["note"] = "" if row["hit"] else "clean record not no_effect_needed"
        else:
            row["hit"] = fit["verdict"] == "unexplained"
            row["invented"] = False
            row["note"] = "" if row["hit"] else "outside the library but not unexplained"
        return row
    row["invented"] = False
    truth_pairs = normalise_keys(raw)
    truth_keys = dict(truth_pairs)
    truth_groups = {}
    for k, _ in truth_pairs:
        if leaf(k) not in SWITCH_LEAVES:
            truth_groups.setdefault(group(k), set()).add(k)
    if not fit["chosen"]:
        row["hit"] = False
        row["note"] = f"nothing chosen ({fit['verdict']})"
        return row
    chosen_keys = []
    chosen_values = {}
    for c in fit["chosen"]:
        pairs = normalise_keys([split_line(s) for s in c["set"]])
        chosen_keys.append([k for k, _ in pairs])
        chosen_values.update(dict(pairs))
    first = touched_groups(chosen_keys[0], truth_groups)
    covered = set(first)
    for keys in chosen_keys[1:]:
        covered |= touched_groups(keys, truth_groups)
    by_look_alike = None
    value_sources = list(fit["chosen"])  # the effects whose values are compared
    for e in fit.get("equivalent", []):
        if isinstance(e, dict):  # fit.json schema 2: each look-alike with its set lines
            pairs = normalise_keys([split_line(x) for x in e["set"]])
            keys = [k for k, _ in pairs]
            # Issue 23: "a look-alike pair counts as right when both are listed as equivalent":
            # where the first chosen effect touches no truth key, a look-alike listed beside it
            # that does names the truth, and its values are the ones compared.
            touched = touched_groups(keys, truth_groups)
            if not first and by_look_alike is None and touched:
                by_look_alike = e["effect"]
                first = touched
                for k, v in pairs:
                    chosen_values.setdefault(k, v)
                value_sources.append(e)
        else:
            keys = effect_name_keys(e, declared.items(e.partition(":")[0]))
        covered |= touched_groups(keys, truth_groups)
    named = bool(first) and covered == set(truth_groups)
    notes = []
    if by_look_alike is not None:
        notes.append(f"named by the look-alike {by_look_alike} listed beside the first chosen")
    if not first:
        notes.append("first chosen touches no truth key")
    elif not named:
        notes.append("not every truth group listed: missing " +
                     ", ".join(sorted(set(truth_groups) - covered)))
    values_ok = True
    off_only_open = True  # every value off is one the fit itself calls open
    texts = []
    open_leaves = {name for c in value_sources for name, p in c.get("parameters", {}).items()
                   if isinstance(p, dict) and p.get("decided") is False}
    # A parameter that sets a key of another name: the lag's filter time constant is its cutoff.
    open_leaves |= {KEY_OF_PARAMETER[name] for name in open_leaves if name in KEY_OF_PARAMETER}
    for k, v in truth_pairs:
        if leaf(k) in NOT_COMPARED_LEAVES or k not in chosen_values:
            continue
        t, f = as_number(v), as_number(chosen_values[k])
        if t is None or f is None:
            continue
        ok, text = compare_value(k, f, t, declared.value(k, truth_keys),
                                 declared.controller_period_s)
        values_ok = values_ok and ok
        if leaf(k) in open_leaves:
            text += " (open)"
        elif not ok:
            off_only_open = False
        text += "" if ok else " !"
        if text not in texts:  # the same key on every AMB / sensor: once
            texts.append(text)
    if named and not texts:
        values_ok = False
        notes.append("no value to compare")
    elif not values_ok:
        notes.append("value off")
    cut_ok = cut >= MIN_CUT
    if not cut_ok:
        notes.append(f"cut {cut:.3g}x < {MIN_CUT:g}x")
    row["value"] = "; ".join(texts)
    row["hit"] = named and values_ok and cut_ok
    # Right but for values the fit reports as not decided by the record (fit.json "decided":
    # false): counted apart, never as right.
    row["hit_but_open"] = (not row["hit"]) and named and bool(texts) and off_only_open and cut_ok
    row["note"] = "; ".join(notes)
    return row


def run_fit(args, record_dir, blind_dir, fit_dir, sets=()):
    """Runs `ambdrop fit` on one blind record (with `sets` as --set lines); returns the seconds
    it took."""
    measured = blind_dir / args.record_file
    if not measured.is_file():
        raise BatteryError(f"{measured}: missing")
    fit_dir.mkdir(parents=True, exist_ok=True)
    cmd = [args.ambdrop, "fit", args.config, "--measured", str(measured), "--out",
           str(fit_dir)] + args.fit_arg
    for s in sets:
        cmd += ["--set", s]
    start = time.monotonic()
    with open(fit_dir / "fit.log", "w") as log:
        log.write(" ".join(cmd) + "\n")
        log.flush()
        rc = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT).returncode
    seconds = time.monotonic() - start
    (fit_dir / "seconds.txt").write_text(f"{seconds:.1f}\n")
    if rc != 0:
        raise BatteryError(f"{record_dir.name}: ambdrop fit exited {rc} (see {fit_dir}/fit.log)")
    if not (fit_dir / "fit.json").is_file():
        raise BatteryError(f"{record_dir.name}: no fit.json in {fit_dir}")
    return seconds


def fmt_cut(cut):
    if cut is None:
        return "-"
    return "inf" if math.isinf(cut) else f"{cut:.3g}x"


def above_noise(part, key):
    return math.sqrt(max(0.0, part[key] ** 2 - part["noise_floor"] ** 2))


def ceiling_cut(fit, ceiling):
    """The cut the truth's own numbers reach on the part the record's fit judged: its residual
    above the noise as declared over what the true numbers leave there. None where the truth's
    fit has no such part (the departing sensors are the record's fit's own choice of channels):
    the whole record's cut, which stood in for it, is another measure, and on a chaotic drop
    it ranked hits of 13-30x on the departing sensors below 3x."""
    name = fit.get("judged_on", "")
    part, best = fit.get(name), ceiling.get(name)
    if part and best:
        before, after = above_noise(part, "rms_before"), above_noise(best, "rms_before")
    elif name in ("", "whole"):
        before = fit["rms_before"]["overall_above_noise"]
        after = ceiling["rms_before"]["overall_above_noise"]
    else:
        return None
    return math.inf if after <= 0.0 else before / after


COLUMNS = ["record", "truth", "verdict", "first chosen", "value vs truth", "cut", "ceiling", "s",
           ""]


def row_cells(r):
    first = r["chosen"].split(", ")[0]
    if r["chosen"].count(", "):
        first += f" (+{r['chosen'].count(', ')})"
    if r["equivalent"]:
        first += f" [eq: {r['equivalent']}]"
    value = r["value"] or "-"
    return [r["record"], r["truth"], r["verdict"], first, value, fmt_cut(r["cut"]),
            fmt_cut(r.get("ceiling")), f"{r['seconds']:.0f}", "HIT" if r["hit"] else "miss"]


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("ambdrop")
    p.add_argument("ambdrop_truth")
    p.add_argument("rig")
    p.add_argument("config")
    p.add_argument("out")
    p.add_argument("--declared", action="store_true")
    p.add_argument("--count", type=int, default=12)
    p.add_argument("--jobs", type=int, default=1)
    p.add_argument("--only", action="append", default=[])
    p.add_argument("--record-file", default="record.csv")
    p.add_argument("--markdown")
    p.add_argument("--score-only", action="store_true")
    p.add_argument("--fit-arg", action="append", default=[])
    p.add_argument("--ceiling", action="store_true")
    p.add_argument("--clean-seeds", type=int, default=0)
    p.add_argument("--first-seed", type=int, default=3)
    p.add_argument("--battery-seed", type=int, default=0)
    args = p.parse_args()
    for f in (args.rig, args.config):
        if not Path(f).is_file():
            print(f"battery: {f}: missing", file=sys.stderr)
            return 2
    out = Path(args.out)
    records = out / "records"
    failures = []
    try:
        if not args.score_only:
            for b in (args.ambdrop, args.ambdrop_truth):
                if not os.access(b, os.X_OK):
                    raise BatteryError(f"{b}: not an executable")
            records.mkdir(parents=True, exist_ok=True)
            if args.clean_seeds > 0:
                plan = []
                for k in range(args.clean_seeds):
                    seed = args.first_seed + k
                    name = f"{k:02d}_clean_s{seed}"
                    gen = subprocess.run([args.ambdrop_truth, "--rig", args.rig, "--effect",
                                          "clean", "--seed", str(seed), "--out",
                                          str(records / name), "--si"],
                                         capture_output=True, text=True)
                    if gen.returncode != 0:
                        raise BatteryError(f"ambdrop_truth --effect clean --seed {seed} exited "
                                           f"{gen.returncode}: {gen.stderr.strip()}")
                    plan.append({"record": name, "blind": f"{name}/blind"})
                (records / "battery.json").write_text(json.dumps(plan, indent=1) + "\n")
            else:
                mode = (["--battery-declared", str(records), "--count", str(args.count)]
                        if args.declared else ["--battery", str(records)])
                if args.battery_seed > 0:
                    mode += ["--first-seed", str(args.battery_seed)]
                gen = subprocess.run([args.ambdrop_truth, "--rig", args.rig] + mode + ["--si"],
                                     capture_output=True, text=True)
                if gen.returncode != 0:
                    raise BatteryError(f"ambdrop_truth {mode[0]} exited {gen.returncode}: "
                                       f"{gen.stderr.strip()}")
        index_file = records / "battery.json"
        if not index_file.is_file():
            raise BatteryError(f"{index_file}: missing")
        plan = json.loads(index_file.read_text())
        if args.only:
            def entry(e):
                f = records / e["record"] / "truth.json"
                return json.loads(f.read_text()).get("entry") if f.is_file() else None
            plan = [e for e in plan if e["record"] in args.only or
                    e["record"].split("_", 1)[1].rsplit("_s", 1)[0] in args.only or
                    entry(e) in args.only]
            if not plan:
                raise BatteryError(f"--only {args.only}: no such record or effect kind")
        # Draws the generator refused (their drop left the physics both simulators model, e.g.
        # the rotor at an AMB's poles) are listed with its reason and not scored.
        not_made = [e for e in plan if "not_made" in e]
        plan = [e for e in plan if "not_made" not in e]
        declared = Declared(args.ambdrop, args.config)
    except BatteryError as e:
        print(f"battery: {e}", file=sys.stderr)
        return 1

    seconds = {}
    if not args.score_only:
        print(f"{len(plan)} records, {args.jobs} at a time: {out}/fits/<record>/fit.json",
              flush=True)
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            futures = {pool.submit(run_fit, args, records / e["record"], records / e["blind"],
                                   out / "fits" / e["record"]): e["record"] for e in plan}
            for fut in concurrent.futures.as_completed(futures):
                name = futures[fut]
                try:
                    seconds[name] = fut.result()
                    print(f"  fitted {name} in {seconds[name]:.0f} s", flush=True)
                except BatteryError as e:
                    failures.append(str(e))
                    print(f"  FAILED {e}", flush=True)
    if args.ceiling and not args.score_only:
        for e in plan:
            sets = json.loads((records / e["record"] / "truth.json").read_text()).get(
                "ambdrop_set", [])
            if not sets:
                continue
            try:
                s = run_fit(args, records / e["record"], records / e["blind"],
                            out / "fits" / e["record"] / "ceiling", sets)
                print(f"  ceiling of {e['record']} in {s:.0f} s", flush=True)
            except BatteryError as err:
                failures.append(str(err))
                print(f"  FAILED {err}", flush=True)

    rows = []
    for e in plan:
        name = e["record"]
        truth_file = records / name / "truth.json"
        fit_file = out / "fits" / name / "fit.json"
        missing = [f for f in (truth_file, fit_file) if not f.is_file()]
        if missing:
            failures.append(f"{name}: missing " + ", ".join(map(str, missing)))
            continue
        row = score(name, json.loads(truth_file.read_text()), json.loads(fit_file.read_text()),
                    declared)
        if name not in seconds:
            s = out / "fits" / name / "seconds.txt"
            seconds[name] = float(s.read_text()) if s.is_file() else math.nan
        row["seconds"] = seconds[name]
        ceiling_file = out / "fits" / name / "ceiling" / "fit.json"
        row["ceiling"] = None
        if ceiling_file.is_file():
            row["ceiling"] = ceiling_cut(json.loads(fit_file.read_text()),
                                         json.loads(ceiling_file.read_text()))
        rows.append(row)

    table = [row_cells(r) for r in rows]
    widths = [max(len(str(c)) for c in col) for col in zip(COLUMNS, *table)] if table else []
    for line in [COLUMNS] + table:
        print("  ".join(str(c).ljust(w) for c, w in zip(line, widths)).rstrip())
    right = sum(r["hit"] for r in rows)
    invented = sum(r["invented"] for r in rows)
    total = f"{right} of {len(rows)} right, {invented} invented"
    but_open = sum(r.get("hit_but_open", False) for r in rows)
    if but_open:
        total += f" ({but_open} more right but for values the fit calls open)"
    if not_made:
        total += f"; {len(not_made)} not made"
    if any(r["ceiling"] is not None for r in rows):
        # Records whose true numbers cannot cut the judged residual 3x cannot be right by the
        # cut rule, whatever the fit does; clean and outside records have no ceiling and stay.
        shown = [r for r in rows if r["ceiling"] is None or r["ceiling"] >= MIN_CUT]
        total += (f"; of the {len(shown)} whose truth reaches a {MIN_CUT:g}x cut, "
                  f"{sum(r['hit'] for r in shown)} right")
    print(total)
    for r in rows:
        if not r["hit"]:
            print(f"  miss {r['record']}: {r['note']}; {r['rms']}")
    for e in not_made:
        print(f"  not made {e['record']}: {e['not_made']}")
    if args.markdown:
        md = ["| " + " | ".join(c or "result" for c in COLUMNS) + " |",
              "|" + " --- |" * len(COLUMNS)]
        for cells in table:
            md.append("| " + " | ".join(str(c).replace("|", "/") for c in cells) + " |")
        md.append("")
        md.append(f"**{total}** (invented: an effect chosen on a clean record).")
        md.append("")
        for r in rows:
            if not r["hit"]:
                md.append(f"- miss `{r['record']}`: {r['note']}; overall {r['rms']}.")
        for e in not_made:
            md.append(f"- not made `{e['record']}` (not scored): {e['not_made']}.")
        Path(args.markdown).write_text("\n".join(md) + "\n")
    if failures:
        for f in failures:
            print(f"battery: {f}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

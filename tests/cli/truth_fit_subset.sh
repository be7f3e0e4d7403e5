#!/usr/bin/env bash
# Issue 15/23 "How it is checked": a subset of the independent records of tools/truth/ (a
# simulator sharing no code with ambdrop) through `ambdrop fit` raw (record.csv in its own units,
# time in ms, no conversion) with the rig's translated config tests/truth/rigid_rotor_a.toml, each held to the scoring rules of tools/truth/battery.py (one
# place for them):
#   - a clean record gives `no_effect_needed` and chooses nothing;
#   - a worn TDB clearance (physics) and a one-axis sensor offset (a sensor effect) are each
#     named first (an effect that sets that key), the value within 20 % of the true change from
#     the declared, the residual above noise cut at least 3x, on the part the verdict judges (a
#     heavier race of seed 15, seen on the speeds only, was held so until session 43: seed 215
#     below holds the race's inertia, and CI's 30 minutes needed its 31 s);
#   - a clean record of another seed (11) whose drop goes into backward whirl where the
#     declared model's noise-free drop rocks gives `no_effect_needed`, nothing chosen, with a
#     run of the declared model whose rotor jitters at the trigger in the record's mode or
#     within the limit (fit.json `jitter_draws`), and no candidate fitted (on every record the
#     draws come first where a later part departs): effects that flip the model's mode cut its
#     speeds 6x (fitted with --jitter-draws=0, the DE TDB's station was named: what the draws
#     are for; that fit, 35-65 s, and the rigid rig's side pull of seed 16, whose `unexplained`
#     the 4-DOF rig's below holds harder, left CI in session 42 for its 30 minutes);
#   - an offset NDE TDB with the DE TDB's friction high: the pair named, both within 20 % (the
#     pair's search along the friction finds it; it had stopped at a y offset 24 % off);
#   - a Dahl ribbon under the NDE housing, with each housing's mass declared (as a rig sheet
#     would give it): the ribbon named, its slipping threshold and stiffness within 20 %;
#   - one TDB's friction high, with the drop's start run from the record's state at the trigger
#     (measurement.trigger_state = "record_start"): the friction named and valued, the start's
#     residual cut 3x (from the model's own state the generator's jitter at the trigger keeps
#     the true friction's start beyond its noise: 2.24x);
#   - on the 4-DOF rig (tests/truth/rigid_fourdof_c.toml: moving races, Hertzian contacts, a
#     declared hold-then-fall power loss): its clean record, an exponential power loss where
#     the hold is declared (the law switched, its time constant within 20 % of the change),
#     and a constant side pull (outside the library), which the magnets' fading law takes most
#     of the way on the drop's start while the speeds refute it: `unexplained`, nothing chosen
#     (its offset-and-friction records, where the friction shows on the speeds only, were held
#     here until sessions 40 and 43, seeds 17 and 617: the second, each look-alike given its
#     partner on the speeds, 77 s of CI's 30 minutes; the kind batteries hold them since);
#   - two records of other draws (`ambdrop_truth --battery --first-seed 201`): the 4-DOF rig's
#     clean seed 202, whose rotor started 0.4 mm/s off the model's rest and whose start departs
#     beyond a limit that a synchronous orbit shift sets (the start's jitter draws span it):
#     `no_effect_needed`; the rigid rig's offset-and-friction seed 217, where the friction moves
#     the start too and the offset fitted beside the declared friction sat 32 % low: the pair
#     named (the friction profiled), the friction and the offset's x within 20 %, its y (a
#     twelfth of x) within 30 % of its change; the rigid rig's clean seed 218, whose start
#     departs from the model's own state beyond even the jitter's limit (2.6 noise floors) and
#     agrees from the lead window's estimate: `no_effect_needed`, the start taken from the
#     record (fit.json trigger_state "record_start");
#   - the rigid rig's static unbalance of seed 406 (6.1e-6 kg m), whose drop's start agrees and
#     whose drop whirls as a draw of the declared model's jitter does: named and valued on the
#     levitated time before the trigger (fit.json judged_on "levitated"), its orbit there;
#   - the rigid rig's offset NDE TDB of seed 203, whose drop whirls backward where the fitted
#     offset's noise-free drop rocks: one run in about 25 of the fitted model with its jitter
#     drawn (64 runs, four times the declared model's) agrees with its speeds, so the offset
#     alone is named and valued; with 16 none did, and a contact stiffness fitted on the speeds
#     beside it moved the offset's y 21 % of its change off;
#   - the rigid rig's heavier NDE race of seed 215: a Palmgren load torque fits its speeds best
#     and a drag torque nearly as well, and the race's inertia (the truth, at its range's end)
#     agrees with the record too, within the agreement limit: listed as equivalent with its
#     value, so the record's look-alikes are named and the truth among them;
#   - the 4-DOF rig's power loss of seed 409, its declared 1 ms hold 1.71 ms long and its time
#     constant as declared: the hold alone (amb_flux_decay_hold_time) named first, within 20 %
#     of its change (the hold and time constant fitted together traded one for the other and
#     left the hold 23 % of its change off);
#   - the rigid rig's chain lag of seed 12 (a 0.33 ms low-pass and a 0.16 ms delay on every
#     sensor, the controller reading through them): the lag shared by every sensor
#     (`sensor_lag`, issue 15 item 5) named first, its delay and cut-off within 20 %;
#   - two declared numbers off (`ambdrop_truth --battery-declared --first-seed 701`'s draws):
#     the rigid rig's DE AMB 14 mm off its station, which the NDE AMB's station and the centre
#     of mass fit exactly as well (the centre of mass midway between the AMBs), and the 4-DOF
#     rig's NDE air gap 23.5 % wide, which its bias current and constant fit as well: the truth
#     named or listed as equivalent, within 20 % of its change (it had gone unlisted: another
#     item of the chosen key's family; a number of its table the screening misjudged);
#   - two of `--first-seed 601`'s draws: the rigid rig's offset-and-friction seed 617, where
#     the friction alone leaves the start within the limit (its sensitivity to the start) but
#     above the noise, and the NDE offset beside it takes it to the noise: the pair named, both
#     within 20 % (the offset had gone unnamed); its offset DE TDB of seed 603, whose start's
#     cost is rough along y: the offset alone, refitted from where a pair put it, within 20 %
#     (its y had stopped 38 % of its change off);
#   - one of `--first-seed 801`'s draws (drawn after the rules above were made): the rigid rig's
#     clean seed 802, whose NDE journal whirls backward where the declared model rocks in every
#     run with its jitter drawn; both journal radii 6 % large took the speeds just within their
#     limit with a model that rocks too: `unexplained`, nothing chosen, the radii as `closest`
#     (they had been named, partly explaining a clean record);
#   - the rigid rig's offset NDE TDB of seed 803 (`--first-seed 801`): the offset named, its x
#     within 20 %, its y (19.7 um beside 74.7, fitted 8 um: the start's cost is flat and rough
#     between 0 and 25 um) within 20 % or called open;
#   - the 4-DOF rig's clean seed 906 (`--clean-seeds 12 --first-seed 901`, drawn after every
#     rule above): its NDE journal rebounds 479 um from its first impact where the declared
#     model's noise-free one rebounds 277 um, so the start departs (0.0224 against 0.0160) and
#     an AMB's station had been named; a run of the declared model with its jitter drawn agrees
#     with the start: `no_effect_needed`, nothing chosen, no candidate fitted;
#   - the same draw's clean seed 912, whose NDE race spins up in 0.10 s where the noise-free
#     model's takes 0.15 s: the closest of the first 16 runs with the jitter drawn leaves its
#     speeds just beyond their limit (0.0359 against 0.0348), so the draws go on (fit.json
#     `jitter_draws.extended`) and the 35th agrees: `no_effect_needed` (a friction coefficient
#     had been named).
#   - the 4-DOF rig's one-axis gain of seed 10 (the NDE sensor's y gain 0.877): the start's one
#     RMS over its 17 channels agrees with the declared model and y_nde alone departs, held to
#     its own noise and widest jitter draw (tools/fit/start_channels.hpp): judged on the
#     departing sensors (fit.json judged_on "sensors"), the gain named and within 20 % (it had
#     been `no_effect_needed`).
#   - the clean seed 911 of `rigid_fourdof_f` (a 4-DOF rig made in session 50, after every
#     rule above; `--clean-seeds 12 --first-seed 901`): its y_nde alone departs on the start by
#     1.18 times its limit, the widest of eight drawn jitters; with four times as many draws
#     (tools/fit/start_channels.cpp, a departure within 1.25 times the limit) it agrees:
#     `no_effect_needed` (a 1 % change of the power loss's slew rate had been named).
#   - `rigid_hc_g` (session 52, after every rule above: contact-law TDBs whose rigid races meet
#     the journal by Hunt-Crossley's law, 25.6 kHz records): its clean seed 1,
#     `no_effect_needed`; its Dahl ribbon of seed 13 under the NDE race, which the rig declares
#     no ribbon for: the dry-friction candidate on the contact's own stiffness, the race riding
#     it with its mass (tools/fit/effect_library.cpp, LinearRibbonOf), named, its threshold
#     within 20 % (456 N against 528), its slipping stiffness called open (it had been
#     `unexplained`: no candidate was offered).
# Every record is fitted before the script fails, so one run shows every outcome.
# Usage: truth_fit_subset.sh AMBDROP_BINARY SOURCE_DIR [AMBDROP_TRUTH_BINARY]
#   (the truth binary defaults to tools/truth/ambdrop_truth beside the ambdrop binary's build
#   tree; without it the script skips, exit 77)
source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
find_truth_tool_or_skip "${3:-}"

# The battery's seeds (ambdrop_truth --battery: kinds in order, seeds 1, 2, ...), so that these
# are the battery's own records. Each case: rig, effect, seed, and optionally more `fit`
# options (its run's directories named after them).
# The Dahl ribbon's record, fitted by a user whose rig sheet gives the housing each ribbon
# carries (the generator's 0.3 kg): the dry-friction candidate then rides a race with mass and
# no viscous part, as the generator's ribbon, and finds the slipping threshold and stiffness.
housings="rigid_rotor_a dahl_ribbon 13 --set tdb.nde.contact_law.outer_race_mass_kg=0.3"
housings+=" --set tdb.de.contact_law.outer_race_mass_kg=0.3"
cases=("rigid_rotor_a clean 1" "rigid_rotor_a clearance_worn 4" "rigid_rotor_a sensor_offset 11"
  "rigid_rotor_a clean 11"
  "rigid_rotor_a misalignment_friction 17"
  "$housings" "rigid_rotor_a friction_one_tdb 5 --set measurement.trigger_state=\"record_start\""
  "rigid_fourdof_c clean 1"
  "rigid_fourdof_c flux_decay_a 8"
  "rigid_fourdof_c side_pull 16" "rigid_fourdof_c clean 202" "rigid_rotor_a misalignment_friction 217"
  "rigid_rotor_a clean 218" "rigid_rotor_a static_unbalance 406"
  "rigid_rotor_a tdb_misalignment 203" "rigid_rotor_a race_inertia 215"
  "rigid_fourdof_c flux_decay_b 409" "rigid_rotor_a chain_lag 12"
  "rigid_rotor_a declared_off 701" "rigid_fourdof_c declared_off 707"
  "rigid_rotor_a misalignment_friction 617" "rigid_rotor_a tdb_misalignment 603"
  "rigid_rotor_a clean 802" "rigid_rotor_a tdb_misalignment 803" "rigid_fourdof_c clean 906" "rigid_fourdof_c clean 912"
  "rigid_fourdof_c sensor_gain_axis 10" "rigid_fourdof_f clean 911" "rigid_hc_g clean 1"
  "rigid_hc_g dahl_ribbon 13")
for c in "${cases[@]}"; do
  read -r rig effect seed extra <<<"$c"
  run="${rig}_${effect}_$seed${extra:+_${extra//[^a-z0-9]/}}"
  "$truth_tool" --rig "$source_dir/tools/truth/rigs/$rig.json" --effect "$effect" --seed "$seed" \
    --out "rec_${rig}_${effect}_$seed" --si >/dev/null ||
    fail "ambdrop_truth $rig --effect $effect exited $?"
  start=$SECONDS
  # shellcheck disable=SC2086 # extra is one option or none
  "$tool" fit "$source_dir/tests/truth/$rig.toml" $extra \
    --measured "rec_${rig}_${effect}_$seed/blind/record.csv" --out "fit_$run" \
    >"fit_$run.txt" 2>&1 ||
    fail "fit of $rig $effect $extra exited $?: $(tail -n 5 "fit_$run.txt")"
  echo "$((SECONDS - start))" >"fit_$run/seconds.txt"
done

python3 - "$source_dir/tools/truth" "$tool" "$source_dir/tests/truth" "${cases[@]}" <<'PY'
import json, sys
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, sys.argv[1])
import battery  # the scoring rules, in one place

expect = {
    "clean": "no_effect_needed",
    "side_pull": "unexplained",
}
declared = {}
failed = []


def decided(fit, key):
    """fit.json's `decided` of the chosen value that sets `key`; None if none sets it."""
    for c in fit["chosen"]:
        if any(line.startswith(key + "=") for line in c.get("set", [])):
            return c["parameters"].get(key.rsplit(".", 1)[1], {}).get("decided")
    return None


for case in sys.argv[4:]:
    rig, effect, seed, *extra = case.split()
    # As the shell names it: "_" and the options' lower-case letters and digits.
    run = f"{rig}_{effect}_{seed}" + ("_" + "".join(
        ch for ch in " ".join(extra) if ch in "abcdefghijklmnopqrstuvwxyz0123456789")
        if extra else "")
    if rig not in declared:
        declared[rig] = battery.Declared(sys.argv[2], f"{sys.argv[3]}/{rig}.toml")
    truth = json.load(open(f"rec_{rig}_{effect}_{seed}/truth.json"))
    fit = json.load(open(f"fit_{run}/fit.json"))
    row = battery.score(effect, truth, fit, declared[rig])
    verdict = expect.get(effect)
    problems = []
    if (rig, effect, seed) == ("rigid_rotor_a", "clean", "802"):
        # The record's NDE journal whirls backward where no run of the declared model does: the
        # effect that cut the speeds left its model rocking, so nothing is named, and the
        # departure is said to be outside the library.
        verdict = "unexplained"
        if "drop the record does not show" not in fit["reason"] or not fit.get("closest"):
            problems.append("the effect out of the record's mode not set aside as closest")
    if verdict is not None and fit["verdict"] != verdict:
        problems.append(f"verdict {fit['verdict']}, expected {verdict}")
    if verdict is not None and fit["chosen"]:
        problems.append("chose " + row["chosen"] + " (expected nothing)")
    if effect == "sensor_gain_axis" and fit.get("judged_on") != "sensors":
        problems.append(f"judged on {fit.get('judged_on')}, expected the departing sensors")
    if effect == "static_unbalance" and fit.get("judged_on") != "levitated":
        problems.append(f"judged on {fit.get('judged_on')}, expected the levitated time")
    pair_values = {
        # The pair and its values, the small y offset held to 30 % of its change.
        ("rigid_rotor_a", "217"): {"tdb.nde.misalignment.x_m": 0.2,
                                   "tdb.nde.misalignment.y_m": 0.3,
                                   "tdb.nde.friction.coefficient": 0.2}}
    if effect == "misalignment_friction" and (rig, seed) in pair_values:
        want = pair_values[(rig, seed)]
        got = dict(line.split("=", 1) for c in fit["chosen"] for line in c.get("set", []))
        sets = dict(line.split("=", 1) for line in truth["ambdrop_set"])
        for key, tol in want.items():
            true = float(sets[key])
            base = declared[rig].value(key, {}) or 0.0
            if key not in got or abs(float(got[key]) - true) > tol * abs(true - base):
                problems.append(f"{key}: {got.get(key)} against {true} (declared {base}), "
                                f"decided {decided(fit, key)}")
        if fit["verdict"] != "explained":
            problems.append(f"verdict {fit['verdict']}")
    elif (rig, effect, seed) == ("rigid_rotor_a", "race_inertia", "215"):
        # A look-alike of the record (issue 23: right when listed as equivalent): the race's
        # inertia among the equivalents, its value within 20 % of the true change, the speeds
        # cut 3x by it, and the verdict `explained`.
        key = "tdb.nde.spin.inertia_kg_m2"
        true = float(dict(line.split("=", 1) for line in truth["ambdrop_set"])[key])
        base = declared[rig].value(key, {})
        alike = [e for e in fit.get("equivalent", []) if any(
            line.startswith(key + "=") for line in e.get("set", []))]
        if fit["verdict"] != "explained":
            problems.append(f"verdict {fit['verdict']}")
        if not alike:
            problems.append(f"no equivalent sets {key}: {battery.equivalent_names(fit)}")
        else:
            e = alike[0]
            got = float(dict(line.split("=", 1) for line in e["set"])[key])
            if abs(got - true) > 0.2 * abs(true - base):
                problems.append(f"{key}: {got} against {true} (declared {base})")
            part = fit[fit["judged_on"]]
            noise = part["noise_floor"]
            above = lambda r: max(0.0, r * r - noise * noise) ** 0.5
            if above(part["rms_before"]) < 3.0 * above(e["rms_after"]):
                problems.append(f"{e['effect']} cuts {part['rms_before']} only to {e['rms_after']}")
    elif (rig, effect, seed) == ("rigid_rotor_a", "clean", "802"):
        pass  # held above: `unexplained` is not the scoring's `no_effect_needed`
    elif (rig, effect, seed) in (("rigid_rotor_a", "tdb_misalignment", "803"),
                                 ("rigid_hc_g", "dahl_ribbon", "13")):
        # 803: its y (19.7 um beside 74.7) the drop's start barely moves between 0 and 25 um:
        # within 20 % of its change, or called open (set back to 0 alone, the record is
        # explained as well); its x within 20 % either way. g's Dahl ribbon: its threshold
        # within 20 %, its slipping stiffness within 20 % or called open.
        if not (row["hit"] or row.get("hit_but_open")):
            problems.append("scoring: " + (row["note"] or "miss"))
    elif not row["hit"]:
        problems.append("scoring: " + (row["note"] or "miss"))
    if (rig, effect, seed) == ("rigid_fourdof_c", "clean", "912") and \
            not (fit.get("jitter_draws") or {}).get("extended"):
        problems.append(f"the draws not extended: {fit.get('jitter_draws')}")
    if (rig, effect, seed) == ("rigid_rotor_a", "clean", "218") and \
            fit.get("trigger_state") != "record_start":
        problems.append(f"the start not taken from the record: {fit.get('trigger_state')}")
    draw = fit.get("jitter_draws")
    if (rig, effect, seed) == ("rigid_rotor_a", "clean", "11") and not (
            draw and (draw["first_within_limit"] > 0 or (
                draw["first_in_record_mode"] > 0 and "backward_whirl" in draw["record_mode"]))):
        problems.append(f"no run of the declared model in the record's whirl: {draw}")
    if draw and (draw["first_within_limit"] > 0 or draw["first_in_record_mode"] > 0) and \
            any(c.get("tried") for c in fit.get("candidates", [])):
        # The draws come before the candidates where a later part departs: once one took the
        # departure, no fit could change the verdict.
        problems.append("candidates fitted although a draw of the jitter took the departure")
    cut = "inf" if row["cut"] == float("inf") else f"{row['cut']:.2g}x"
    seconds = open(f"fit_{run}/seconds.txt").read().strip()
    print(f"{rig:<15} {' '.join([effect, seed] + extra):<24} {fit['verdict']:<17} on {fit.get('judged_on', '?'):<6} "
          f"chosen {row['chosen']:<28} "
          f"{row['value'] or '-'}; cut {cut}; {seconds} s; {truth['description']}")
    if problems:
        failed.append(f"{rig} {effect}: " + "; ".join(problems))
if failed:
    print("FAIL:\n  " + "\n  ".join(failed), file=sys.stderr)
    sys.exit(1)
PY

// Seed 003: "Dynamics of rotor drop on new type catcher bearing", Sec. 2.4 and 3: the rotor
// dropped at 200 Hz onto double-decker catcher bearings (configs/ddcb_rigid.toml) and onto
// single-decker ones (configs/sdcb_rigid.toml), 0.2 s after the drop.
#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "io/config/config_loader.hpp"
#include "rt_core/catcher_bearing_tdb.hpp"
#include "tools/validation/orbit_rms.hpp"
#include "tools/validation/stepped_drop.hpp"
#include "tools/validation/tdb_peaks.hpp"
#include "tools/validation/unbalance_phases.hpp"
#include "tools/validation/validation_cases.hpp"

namespace ambdrop {
namespace {

struct CatcherDrop {
  double peak_normal_N = 0.0;  ///< over both TDBs
  /// RMS journal distance from its mean at the first TDB, from the first contact at either on.
  double amplitude_m = 0.0;
  double inner_race_rad_s = 0.0;         ///< first TDB, at the end
  double intermediate_race_rad_s = 0.0;  ///< 0 without an intermediate race (single decker)
  bool ok = false;
};

CatcherDrop DropAtPhase(const std::string& config_path, int phase) {
  const Model model =
      BuildModel(LoadConfig(config_path, {UnbalancePhaseOverride("rotor", phase)}).params);
  TdbPeakTracker peaks(model.params);
  OrbitRms orbit;
  const SteppedDrop run = RunSteppedDrop(model, 0.2, [&](const Observation& o) {
    peaks.Add(o);
    if (peaks.MaxNormal_N() > 0.0) orbit.Add(o.tdb_journal_xy_m[0][0], o.tdb_journal_xy_m[0][1]);
  });
  CatcherDrop d;
  d.ok = run.status == StepStatus::kOk;
  d.peak_normal_N = peaks.MaxNormal_N();
  d.amplitude_m = orbit.rms_m();
  const int offset = model.tdb_state_offset[0];
  d.inner_race_rad_s = run.final_state.y[offset + CatcherBearingTdb::kSpin];
  const auto& tdb = static_cast<const CatcherBearingTdb&>(*model.tdbs[0]);
  if (tdb.intermediate_offset() >= 0) {
    d.intermediate_race_rad_s =
        run.final_state.y[offset + tdb.intermediate_offset() + CatcherBearingTdb::kSpin];
  }
  return d;
}

// The paper's drops start "in the same initial motion state" (its drop board switches the AMBs
// off at a set phase), which it does not give, and the drop is chaotic: each bearing type is
// compared by its medians over the unbalance phases.
CatcherDrop Drop(const std::string& config_path) {
  std::vector<double> peak, amplitude, inner, intermediate;
  CatcherDrop d;
  d.ok = true;
  for (int k = 0; k < kUnbalancePhases; ++k) {
    const CatcherDrop r = DropAtPhase(config_path, k);
    d.ok = d.ok && r.ok;
    peak.push_back(r.peak_normal_N);
    amplitude.push_back(r.amplitude_m);
    inner.push_back(r.inner_race_rad_s);
    intermediate.push_back(r.intermediate_race_rad_s);
  }
  d.peak_normal_N = Median(peak);
  d.amplitude_m = Median(amplitude);
  d.inner_race_rad_s = Median(inner);
  d.intermediate_race_rad_s = Median(intermediate);
  return d;
}

// Not closed (issue 5). The paper (Sec. 2.4) reads the amplitude off Fig. 6, the left journal's
// orbit 0-0.2 s after the drop ("the rotor jumping height using SDCBs is higher ... the amplitudes
// of rotor vibration are decreased by at least 28 %"), from "initial vibration displacement 7 um
// and velocity 0.6 m/s ... angle between the velocity and the horizontal axis 90 deg". ambdrop's
// DDCB orbit is never 20 % smaller under any reading tried (DDCB vs SDCB, 0.2 s). Medians over
// the 8 unbalance phases, as the case compares them: RMS +39 %, peak-to-peak x +27 %, y +26 %,
// largest radius +7 %, and the DDCB's journal jumps higher (its highest point 60 um below the
// centre, the SDCB's 68 um); with un-lubricated friction the RMS is +6 % (mu 0.2, 0.25) and
// +15 % (mu 0.3), the force 27-30 % lower. Single drops, at unbalance phase 0:
//   - levitated start (orbit 7.6 um, 9.6 mm/s: the paper's 7 um): RMS +27 %, peak-to-peak x
//     +18 %, y +9 %, largest radius 145 vs 135 um;
//   - the same with the unbalance phase set so the journal moves straight up at the drop (the
//     paper's 90 deg): RMS +13 %, peak-to-peak x +27 %, y +7 %;
//   - and 0.6 m/s upwards added at the drop: RMS +3 %, peak-to-peak y +16 %, radius 211 vs
//     182 um (0.6 m/s down at phase 0: RMS -13 %, peak-to-peak y +16 %);
//   - the unbalance phase over 0-2 pi in 8 steps: the DDCB's RMS is -4 % to +64 % off the SDCB's.
// The peak force is 26-33 % lower for the DDCB in all of these. After the first impacts the
// journal rocks in the bottom of the race at the pendulum frequency sqrt(g / c) (45 Hz); the
// double decker's series compliance (second bearing, its 10 um clearance, the intermediate race)
// lets it swing wider, and its extra contact damping (Table 2's 1000 N s/m per ball) does not
// make up for it. Assumed values: intermediate race 13 / 52 g: RMS +23 / +10 %; ball damping
// ramp 1e-8 m: +12 %; impact damping 5 kN s/m: +19 %; friction 0.2: +19 %. Two settings turn
// it, each pushing the force drop out of its 10-35 % band: friction 0.3 (RMS -24 %, force
// -40 %) and ball contact damping 5x the paper's Table 2 (RMS -46 %, force -57 %).
constexpr const char* kAmplitudeKnownFailure =
    "issue 5: the DDCB's journal orbit is larger than the SDCB's (medians over 8 unbalance "
    "phases: RMS +39 %, peak-to-peak x +27 %, y +26 %, and it jumps higher), and never 20 % "
    "smaller with the paper's drop conditions (velocity straight up, +0.6 m/s) or with "
    "un-lubricated friction (mu 0.2-0.3: RMS +6 to +15 %): the double decker's series compliance "
    "lets the journal rock wider in the race (see seed003_cases.cpp)";

}  // namespace

std::vector<ValidationCheck> Seed003DoubleDecker(const std::string& configs_dir) {
  const char* kCase = "seed003 Sec. 3 (DDCB vs SDCB)";
  const CatcherDrop ddcb = Drop(configs_dir + "/ddcb_rigid.toml");
  const CatcherDrop sdcb = Drop(configs_dir + "/sdcb_rigid.toml");
  const auto change = [](double ddcb_value, double sdcb_value) {
    return fmt::format("{:+.1f} %", (ddcb_value / sdcb_value - 1.0) * 100.0);
  };

  std::vector<ValidationCheck> checks;
  // "The DDCB lowers peak contact forces by about 15-27 %": accepted 10-35 %.
  const double force_reduction = 1.0 - ddcb.peak_normal_N / sdcb.peak_normal_N;
  ValidationCheck force =
      TrendCheck(kCase, "peak contact force, DDCB vs SDCB", "15-27 % lower",
                 change(ddcb.peak_normal_N, sdcb.peak_normal_N),
                 sdcb.peak_normal_N > 0.0 && force_reduction >= 0.10 && force_reduction <= 0.35);
  force.criterion = "10-35 % lower";
  checks.push_back(force);
  // "... and vibration amplitudes by at least 28 %": accepted at least 20 %.
  ValidationCheck amplitude =
      TrendCheck(kCase, "vibration amplitude (RMS), DDCB vs SDCB", ">= 28 % lower",
                 change(ddcb.amplitude_m, sdcb.amplitude_m),
                 sdcb.amplitude_m > 0.0 && ddcb.amplitude_m <= 0.8 * sdcb.amplitude_m);
  amplitude.criterion = ">= 20 % lower";
  if (!amplitude.pass) amplitude.known_failure = kAmplitudeKnownFailure;
  checks.push_back(amplitude);
  // The intermediate race "takes ~17 % of the inner race speed" (the paper's experiment);
  // accepted: a fraction between 5 and 50 %.
  constexpr double kPublishedSpeedRatio = 0.17;
  const double ratio = ddcb.intermediate_race_rad_s / ddcb.inner_race_rad_s;
  ValidationCheck speed = TrendCheck(kCase, "intermediate / inner race speed (DDCB)",
                                     fmt::format("{:.0f} %", kPublishedSpeedRatio * 100.0),
                                     fmt::format("{:.1f} %", ratio * 100.0),
                                     ddcb.inner_race_rad_s > 0.0 && ratio > 0.05 && ratio < 0.5);
  speed.deviation = ratio / kPublishedSpeedRatio - 1.0;
  speed.criterion = "5-50 %";
  checks.push_back(speed);
  if (!ddcb.ok || !sdcb.ok) {
    checks.push_back(TrendCheck(kCase, "all drops run to the end", "yes", "a run diverged", false));
  }
  return checks;
}

}  // namespace ambdrop

// The truth generator's flexible, magnet-biased, firmware-controlled rig (issue 24) against
// closed forms it must obey, each computed here from the textbook formula, not from the
// generator: free-free Euler-Bernoulli beam frequencies, a cylinder's inertias, Tustin's
// prewarp at the notch, windage's hyperbolic coast-down, the slew-limited ramp, and a magnet's
// bias that keeps pulling after the power is gone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "declared_off.hpp"
#include "drop_run.hpp"
#include "effects.hpp"
#include "firmware_controller.hpp"
#include "rig.hpp"
#include "rotor_modes.hpp"

namespace ambdrop_truth::truth_flexible_rig_test {
namespace {

constexpr double kPi = std::numbers::pi;

Rig RigB() {
  std::string path = AMBDROP_SOURCE_DIR;
  path.append("/tools/truth/rigs/flexible_pm_b.json");
  return ReadRig(path);
}

RunOptions Quiet() {
  RunOptions o;
  o.add_noise = false;
  return o;
}

FlexibleShaftRig UniformShaft(double length_m, double diameter_m, int elements) {
  FlexibleShaftRig s;
  s.enabled = true;
  s.youngs_modulus_Pa = 2.1e11;
  s.density_kg_m3 = 7850.0;
  s.segments.push_back({length_m, diameter_m, 0.0, elements});
  return s;
}

// Free-free beams: omega_n = (beta_n L)^2 sqrt(E I / (rho A L^4)) with beta_n L = 4.7300,
// 7.8532, 10.9956 (Euler-Bernoulli; e.g. Blevins, "Formulas for Natural Frequency and Mode
// Shape", Table 8-1). At L/D = 500 the rotary inertia is negligible (1e-5) and the 40 cubic
// elements converged: within 1e-4. At L/D = 50 the Rayleigh beam's rotary inertia lowers each
// frequency, by under 0.3 %.
TEST(TruthFlexibleRig, FreeFreeBeamsMatchEulerBernoulli) {
  const double beta_l[] = {4.730040745, 7.853204624, 10.99560784};
  for (const double D : {0.002, 0.02}) {
    const double L = 1.0;
    const std::vector<double> w = FreeFreeBendingFrequencies(UniformShaft(L, D, 40), {});
    const double area = kPi * D * D / 4.0, second = kPi * std::pow(D, 4) / 64.0;
    const double scale = std::sqrt(2.1e11 * second / (7850.0 * area * std::pow(L, 4)));
    ASSERT_GE(w.size(), 3u);
    for (int n = 0; n < 3; ++n) {
      const double euler_bernoulli = beta_l[n] * beta_l[n] * scale;
      if (D < 0.01) {
        EXPECT_NEAR(w[n] / euler_bernoulli, 1.0, 1e-4) << "mode " << n + 1;
      } else {
        EXPECT_LT(w[n], euler_bernoulli) << "mode " << n + 1;
        EXPECT_NEAR(w[n] / euler_bernoulli, 1.0, 3e-3) << "mode " << n + 1;
      }
    }
  }
}

// A cylinder with a disc: m, the centre of mass, It about it (m L^2 / 12 + m r^2 / 4 plus
// parallel axes) and Ip (m r^2 / 2) to rounding: the consistent mass matrix integrates the
// rigid-body fields exactly.
TEST(TruthFlexibleRig, ShaftInertiaIsTheCylindersAndTheDiscs) {
  FlexibleShaftRig shaft = UniformShaft(0.8, 0.06, 8);
  shaft.start_m = 0.1;
  shaft.discs.push_back({0.3, 6.0, 0.02, 0.035});
  const RotorRig r = ShaftInertia(shaft);
  const double rad = 0.03, ms = 7850.0 * kPi * rad * rad * 0.8, zs = 0.5;
  const double m = ms + 6.0, zc = (ms * zs + 6.0 * 0.3) / m;
  const double it = ms * (0.8 * 0.8 / 12.0 + rad * rad / 4.0) + ms * (zs - zc) * (zs - zc) + 0.02 +
                    6.0 * (0.3 - zc) * (0.3 - zc);
  EXPECT_NEAR(r.mass_kg, m, 1e-12 * m);
  EXPECT_NEAR(r.centre_of_mass_m, zc, 1e-12);
  EXPECT_NEAR(r.transverse_inertia_kg_m2, it, 1e-11 * it);
  EXPECT_NEAR(r.polar_inertia_kg_m2, ms * rad * rad / 2.0 + 0.035, 1e-12);
}

// Tustin prewarped at the notch frequency gives the continuous response there exactly; plain
// Tustin moves the notch (frequency warping, w_d = (2/T) atan(w T / 2)).
TEST(TruthFlexibleRig, PrewarpedTustinHitsTheNotchFrequency) {
  FirmwareSectionRig notch;
  notch.kind = FirmwareSectionRig::Kind::kNotch;
  notch.frequency_Hz = 470.0;
  notch.pole_damping = 0.3;
  notch.zero_damping = 0.02;
  const double T = 1.0 / 5000.0, w0 = 2.0 * kPi * 470.0;
  const Biquad plain = Discretise(notch, T);
  notch.prewarp_Hz = 470.0;
  const Biquad warped = Discretise(notch, T);
  const std::complex<double> at_notch = SectionResponse(notch, w0);
  EXPECT_NEAR(std::abs(at_notch), 0.02 / 0.3, 1e-12);
  EXPECT_NEAR(std::abs(warped.Response(w0, T) - at_notch), 0.0, 1e-12);
  EXPECT_GT(std::abs(plain.Response(w0, T) - at_notch), 1e-2);
  // Both keep the DC gain of 1.
  EXPECT_NEAR(std::abs(warped.Response(0.0, T)), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(plain.Response(0.0, T)), 1.0, 1e-12);
}

// With windage alone (no contact friction: the TDBs' coefficient 0), Ip W' = -c W^2 gives
// W(t) = W0 / (1 + c W0 t / Ip) after the motor stops at the trigger.
TEST(TruthFlexibleRig, WindageCoastDownIsHyperbolic) {
  Rig rig = RigB();
  for (TdbRig& t : rig.tdbs) t.friction_coefficient = 0.0;
  rig.acquisition.settle_s = 0.0;
  const RunResult run = RunDrop(rig, 1, Quiet());
  ASSERT_TRUE(run.finite);
  const double w0 = rig.spin_speed_rad_s, c = rig.coast_down.windage_N_m_s2;
  const double ip = rig.rotor.polar_inertia_kg_m2, tp = rig.acquisition.trigger_time_s;
  int checked = 0;
  for (const RecordRow& row : run.rows) {
    if (row.t_s < tp) {
      EXPECT_EQ(row.rotor_speed_rad_s, w0);
      continue;
    }
    const double expected = w0 / (1.0 + c * w0 * (row.t_s - tp) / ip);
    EXPECT_NEAR(row.rotor_speed_rad_s, expected, 1e-9 * w0) << "t " << row.t_s;
    ++checked;
  }
  EXPECT_GT(checked, 4000);
  EXPECT_LT(run.rows.back().rotor_speed_rad_s, w0 - 5.0);  // the loss shows: > 50 rpm
}

// The DC link collapses at the trigger: each coil control current falls at the slew rate S
// from the value c0 it carried and stays at zero from |c0| / S on.
TEST(TruthFlexibleRig, RampReachesZeroAtTheCurrentOverTheSlewRate) {
  const Rig rig = RigB();
  const RunResult run = RunDrop(rig, 1, Quiet());
  ASSERT_TRUE(run.finite);
  const double tp = rig.acquisition.trigger_time_s, S = rig.power_loss.slew_rate_A_per_s;
  const auto at = [&](double t) {
    return *std::find_if(run.rows.begin(), run.rows.end(),
                         [&](const RecordRow& r) { return r.t_s >= t - 1e-9; });
  };
  const RecordRow start = at(tp);
  for (int a = 0; a < 2; ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      const double c0 = start.current_A[a][axis];
      const double zero_at = tp + std::abs(c0) / S;
      if (axis == 1) {
        ASSERT_GT(std::abs(c0), 0.5);  // the vertical axes carry the weight
      }
      if (std::abs(c0) < 0.01) continue;  // x: the rotor's small static offset only
      const RecordRow mid = at(tp + 0.5 * (zero_at - tp));
      EXPECT_NEAR(mid.current_A[a][axis], c0 - std::copysign(S * (mid.t_s - tp), c0), 1e-9);
      EXPECT_EQ(at(zero_at + 1e-4).current_A[a][axis], 0.0);
      EXPECT_NE(at(zero_at - 1e-4).current_A[a][axis], 0.0);
    }
  }
}

// A magnet's bias stays after power loss: with the coil currents gone at once, the rotor at
// an AMB feels f = k I0^2 (1/(g0 - u)^2 - 1/(g0 + u)^2) ~ ks u, ks = 4 k I0^2 / g0^3, a
// negative stiffness. The rotor (its centre of mass midway between the AMBs) then leaves
// the centre as u'' = w^2 u - g, w^2 = 2 ks / m: |u| = g / w^2 (cosh w t - 1), faster than
// free fall; with an electromagnet bias the force is gone and it falls as g t^2 / 2.
TEST(TruthFlexibleRig, AMagnetBiasKeepsPullingAfterPowerLoss) {
  Rig rig = RigB();
  rig.power_loss.form = FluxDecayForm::kInstant;
  rig.acquisition.sensor_quantisation_m = 0.0;
  rig.acquisition.record_length_s = rig.acquisition.trigger_time_s + 0.006;
  const RunResult magnet = RunDrop(rig, 1, Quiet());
  for (AmbRig& a : rig.ambs) {
    a.permanent_magnet_bias = false;
    a.coil_current_limit_A = 2.0 * a.bias_current_A;
  }
  const RunResult electro = RunDrop(rig, 1, Quiet());
  ASSERT_TRUE(magnet.finite && electro.finite);
  const double tp = rig.acquisition.trigger_time_s;
  const auto drop = [&](const RunResult& run, int s, double t) {
    const auto before = std::find_if(run.rows.begin(), run.rows.end(),
                                     [&](const RecordRow& r) { return r.t_s >= tp - 1e-9; });
    const auto after = std::find_if(run.rows.begin(), run.rows.end(),
                                    [&](const RecordRow& r) { return r.t_s >= tp + t - 1e-9; });
    const double dx = after->displacement_m[s][0] - before->displacement_m[s][0];
    const double dy = after->displacement_m[s][1] - before->displacement_m[s][1];
    return std::hypot(dx, dy);
  };
  const AmbRig& a = rig.ambs[0];
  const double ks = 4.0 * a.electromagnet_constant_N_m2_per_A2 * a.bias_current_A *
                    a.bias_current_A / std::pow(a.nominal_gap_m, 3);
  const double w = std::sqrt(2.0 * ks / rig.rotor.mass_kg), g = rig.gravity_m_s2;
  // Before the journals reach their TDBs (0.2 mm).
  for (const double t : {4e-3, 5e-3}) {
    const double free_fall = 0.5 * g * t * t;
    const double pulled = g / (w * w) * (std::cosh(w * t) - 1.0);
    for (int s = 0; s < 2; ++s) {
      // Within what the released sag's bending adds at the sensors.
      EXPECT_NEAR(drop(electro, s, t), free_fall, 0.05 * free_fall) << "sensor " << s;
      EXPECT_NEAR(drop(magnet, s, t), pulled, 0.05 * pulled) << "sensor " << s;
    }
    EXPECT_GT(pulled, 1.08 * free_fall);  // the two are told apart
  }
}

// A drop that leaves the physics the generator models is refused, not written: on this rig's
// magnet-biased AMBs, a soft dry-friction ribbon under the NDE TDB (the battery's draw, seed 13)
// lets the rotor sink until the magnets pull it to their poles, where the AMB law is clamped
// and nothing models the strike. The clean drop stays well inside the gap, as its sensors
// beside the magnets read it, not through the generator's own check.
TEST(TruthFlexibleRig, ARotorAtTheMagnetsPolesIsNoTdbDrop) {
  const auto deepest = [](const Rig& rig, RunResult* run) {
    double fraction = 0.0;  // of the gap, at either sensor (each beside its AMB), either axis
    *run = RunDrop(rig, 13, Quiet());
    for (const RecordRow& row : run->rows) {
      for (int s = 0; s < 2; ++s) {
        for (int axis = 0; axis < 2; ++axis) {
          fraction = std::max(fraction, std::abs(row.displacement_m[s][axis]) /
                                            rig.ambs[static_cast<std::size_t>(s)].nominal_gap_m);
        }
      }
    }
    return fraction;
  };
  Rig clean = RigB();
  ApplyEffect("clean", 13, &clean);
  RunResult clean_run;
  const double clean_depth = deepest(clean, &clean_run);
  EXPECT_TRUE(clean_run.left_physics.empty()) << clean_run.left_physics;
  EXPECT_LT(clean_depth, 0.7);  // the TDBs (0.2 mm) hold it well inside the 0.5 mm gap

  Rig soft = RigB();
  ApplyEffect("dahl_ribbon", 13, &soft);
  RunResult soft_run;
  const double soft_depth = deepest(soft, &soft_run);
  ASSERT_FALSE(soft_run.left_physics.empty());
  EXPECT_NE(soft_run.left_physics.find("AMB nde's poles"), std::string::npos)
      << soft_run.left_physics;
  // The sensors beside the magnets see the rotor reach the poles (and the clamped law lets it
  // run on, which is why the record is refused).
  EXPECT_GT(soft_depth, 0.95);
}

// The controller reads through the acquisition chain's lag, so a long lag spends the loop's phase
// margin: on this rig a 0.22 ms low-pass and a 0.25 ms delay (seed 212's first draw) leave the
// rotor unlevitated (it went onto the poles before the trigger, and the battery stopped). The
// chain-lag record draws again until its rig levitates, as declared numbers are drawn.
TEST(TruthFlexibleRig, AChainLagThatCostsTheLoopItsMarginIsDrawnAgain) {
  Rig first = RigB();
  first.acquisition.lag_time_constant_s = 0.22277e-3;
  first.acquisition.lag_delay_s = 0.24581e-3;
  EXPECT_FALSE(Levitates(first, 212));
  Rig lagged = RigB();
  const Truth t = ApplyEffect("chain_lag", 212, &lagged);
  EXPECT_TRUE(Levitates(lagged, 212)) << t.description;
  EXPECT_NE(t.description.find("did not levitate"), std::string::npos) << t.description;
  // Still a lag the records can show: 0.2-0.7 ms in all.
  const double total = lagged.acquisition.lag_time_constant_s + lagged.acquisition.lag_delay_s;
  EXPECT_GT(total, 0.2e-3);
  EXPECT_LT(total, 0.7e-3);
}

// Every number of the rig file is checked before it becomes a count or a frequency: a mode
// count of 1e300 (once cast to int unchecked) and a prewarp above half the controller rate are
// refused, naming the key.
TEST(TruthFlexibleRig, RigNumbersAreCheckedBeforeUse) {
  std::string path = AMBDROP_SOURCE_DIR;
  path.append("/tools/truth/rigs/flexible_pm_b.json");
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  const auto refused = [&](const std::string& from, const std::string& to) {
    std::string edited = text.str();
    const std::size_t at = edited.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    edited.replace(at, from.size(), to);
    const std::string file =
        (std::filesystem::temp_directory_path() / "truth_rig_checked.json").string();
    std::ofstream(file) << edited;
    try {
      (void)ReadRig(file);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("loaded");
  };
  EXPECT_NE(refused("\"bending_modes\": 3", "\"bending_modes\": 1e300").find("bending_modes"),
            std::string::npos);
  EXPECT_NE(refused("\"prewarp_Hz\": 430.0", "\"prewarp_Hz\": 3000.0").find("prewarp_Hz"),
            std::string::npos);
}

// declared_off on this rig lists its own numbers (a flexible shaft's, a firmware's, the ramp's,
// the windage), and every one of them changes the truth run: against the clean run of the same
// seed some channel departs by more than its noise sigma, rms over a short record (20 ms
// levitated, 35 ms of drop); the windage, which only slows the rotor, over the whole record.
// A flexible shaft's rigid-body numbers follow its discs and segments.
TEST(TruthFlexibleRig, DeclaredOffListsThisRigsNumbersAndEachMovesTheRecord) {
  const std::uint64_t seed = 3;
  Rig short_rig = RigB();
  short_rig.acquisition.trigger_time_s = 0.02;
  short_rig.acquisition.record_length_s = 0.055;
  const Rig full_rig = RigB();
  const std::vector<DeclaredEntry> entries = DeclaredOffEntries(short_rig);
  // 2 material + 5 segments + 4 x 4 discs + windage + ramp + 3 PD + 2 lead + 3 notch + 2 loop +
  // 2 gains + delay + 2 x 4 AMB + 2 x 5 sensor + 2 x 8 TDB numbers.
  ASSERT_EQ(entries.size(), 72u);
  const RunResult short_clean = RunDrop(short_rig, seed);
  const RunResult full_clean = RunDrop(full_rig, seed);
  const auto speed_sigma = short_rig.acquisition.speed_noise_rpm * 2.0 * kPi / 60.0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const DeclaredEntry& e = entries[i];
    SCOPED_TRACE(e.name);
    EXPECT_EQ(e.name.find("rotor.mass_kg"), std::string::npos);
    const bool full = e.name.starts_with("coast_down.") || e.name.ends_with("viscous_drag_N_m_s");
    Rig rig = full ? full_rig : short_rig;
    const Truth t =
        ApplyDraw(entries, DrawDeclaredOff(rig, entries, static_cast<int>(i), seed, 0), 0, &rig);
    ASSERT_FALSE(t.ambdrop_keys.empty());
    EXPECT_EQ(t.ambdrop_keys[0].first, e.ambdrop_key);
    if (e.name.starts_with("rotor.shaft.")) {
      const RotorRig derived = ShaftInertia(rig.shaft);
      EXPECT_EQ(rig.rotor.mass_kg, derived.mass_kg);
      EXPECT_EQ(rig.rotor.polar_inertia_kg_m2, derived.polar_inertia_kg_m2);
    }
    const RunResult run = RunDrop(rig, seed);
    if (!run.finite) continue;  // a draw that does not levitate is drawn again by the effect
    const RunResult& clean = full ? full_clean : short_clean;
    const std::size_t n = std::min(run.rows.size(), clean.rows.size());
    double worst = 0.0;
    const auto channel = [&](auto get, double sigma) {
      double sum = 0.0;
      for (std::size_t j = 0; j < n; ++j)
        sum += std::pow((get(run.rows[j]) - get(clean.rows[j])) / sigma, 2);
      worst = std::max(worst, std::sqrt(sum / static_cast<double>(n)));
    };
    for (int s = 0; s < 2; ++s) {
      for (int axis = 0; axis < 2; ++axis) {
        channel([=](const RecordRow& r) { return r.displacement_m[s][axis]; },
                rig.acquisition.sensor_noise_m);
        channel([=](const RecordRow& r) { return r.current_A[s][axis]; },
                rig.acquisition.current_noise_A);
      }
      channel([=](const RecordRow& r) { return r.race_speed_rad_s[s]; }, speed_sigma);
    }
    channel([](const RecordRow& r) { return r.rotor_speed_rad_s; }, speed_sigma);
    EXPECT_GT(worst, 1.0);
  }
  // The ramp's slew rate is rig-wide; ambdrop declares it per AMB: both keys carry it.
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (entries[i].name != "power_loss.slew_rate_A_per_s") continue;
    Rig rig = short_rig;
    const Truth t =
        ApplyDraw(entries, DrawDeclaredOff(rig, entries, static_cast<int>(i), seed, 0), 0, &rig);
    ASSERT_EQ(t.ambdrop_keys.size(), 2u);
    EXPECT_EQ(t.ambdrop_keys[0].second, t.ambdrop_keys[1].second);
    EXPECT_NE(t.ambdrop_keys[0].first, t.ambdrop_keys[1].first);
  }
}

}  // namespace
}  // namespace ambdrop_truth::truth_flexible_rig_test

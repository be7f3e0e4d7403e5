// How often `ambdrop fit` gets it right on records it was not tuned on (issue 6): for each rig
// config and each effect its library offers there, a truth record is made with that effect on
// at a seeded random strength, sign and station, at half the rig's step, with sensor noise and
// noise on currents, forces and speeds; the rig as declared is then fitted to it. A case is a hit
// when the fit names the effect first, calls the record explained, and recovers the effect's
// departure from the declared model within 20 % per parameter (angles within 0.35 rad).
// Prints one line per case and the hit rate per rig and overall. Not a test: it takes minutes.
// Run: build/tests/fit_battery [--after-s 0.15] [--rigs a.toml,b.toml] [--seed 1]
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "controller_if/boundary/portable_random.hpp"
#include "io/files/measured_csv.hpp"
#include "rt_core/modal_reduction.hpp"
#include "test_configs.hpp"
#include "tools/fit/effect_library.hpp"
#include "tools/fit/fit_record.hpp"
#include "tools/fit/measured_record_maker.hpp"

namespace ambdrop {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Where to write each case's record and [measurement] table ("": nowhere).
std::string g_keep_dir;
int g_case = 0;

void Keep(const ModelParams& truth, const SyntheticMeasurement& made) {
  if (g_keep_dir.empty()) return;
  const std::string stem = fmt::format("{}/case{:03d}", g_keep_dir, g_case);
  WriteMeasuredCsv(stem + ".csv", made.record);
  std::FILE* f = std::fopen((stem + ".toml").c_str(), "w");
  if (f == nullptr) return;
  std::fputs(MeasurementTableToml(truth, made.measurement).c_str(), f);
  std::fclose(f);
}

struct Truth {
  std::vector<double> values;    ///< the effect's parameters in the truth record
  std::vector<double> declared;  ///< the same parameters as the declared rig has them
};

double Between(PortableRandom* r, double lo, double hi) {
  return lo + (hi - lo) * r->Uniform();
}
double Sign(PortableRandom* r) {
  return r->Uniform() < 0.5 ? -1.0 : 1.0;
}

const TdbParams& TdbOf(const ModelParams& p, const std::string& effect) {
  const std::string name = effect.substr(effect.find(':') + 1);
  for (const TdbParams& t : p.tdbs) {
    if (t.name == name) return t;
  }
  return p.tdbs.front();
}

const SensorParams& SensorOf(const ModelParams& p, const std::string& effect) {
  const std::string name = effect.substr(effect.find(':') + 1);
  for (const SensorParams& s : p.sensors) {
    if (s.name == name) return s;
  }
  return p.sensors.front();
}

// A strength an engineer would call plainly present, but not the library's probe (the fit's
// own generous value): each draw is from a range set by the rig's own scales.
Truth Draw(const Effect& e, const ModelParams& declared, PortableRandom* r) {
  const std::string& f = e.family;
  Truth t;
  t.declared.assign(e.parameters.size(), 0.0);
  if (f == "tdb_misalignment") {
    const double c = TdbOf(declared, e.name).clearance_m;
    t.values = {Sign(r) * Between(r, 0.15, 0.45) * c, Sign(r) * Between(r, 0.15, 0.45) * c};
  } else if (f == "tdb_clearance") {
    t.declared = {TdbOf(declared, e.name).clearance_m};
    t.values = {t.declared[0] *
                (r->Uniform() < 0.75 ? Between(r, 1.15, 1.45) : Between(r, 0.8, 0.9))};
  } else if (f == "friction_coefficient") {
    const double mu = e.parameters[0].starts.front();
    t.declared = {mu};
    t.values = {r->Uniform() < 0.5 ? mu * Between(r, 0.4, 0.7)
                                   : std::min(0.8, mu * Between(r, 1.4, 2.0))};
  } else if (f == "unbalance") {  // static or couple
    // A synchronous force of 10-50 % of the rotor's weight at the drop speed.
    const double weight_N = BuildReducedRotor(declared).mass_kg * 9.81;
    const double spin = std::max(declared.simulation.spin_speed_rad_s, 1.0);
    t.values = {Between(r, 0.1, 0.5) * weight_N / (spin * spin), Between(r, -kPi, kPi)};
  } else if (f == "amb_flux_decay") {
    t.values = {Between(r, 2e-3, 1e-2)};
  } else if (f == "sensor_runout") {
    const double c = declared.tdbs.front().clearance_m;
    t.values = {Between(r, 0.03, 0.1) * c, Between(r, -kPi, kPi)};
  } else if (f == "sensor_gain_offset") {
    const SensorParams& s = SensorOf(declared, e.name);
    const double c = declared.tdbs.front().clearance_m;
    t.declared = {s.gain, s.offset_m};
    t.values = {s.gain * (1.0 + Sign(r) * Between(r, 0.05, 0.15)),
                s.offset_m + Sign(r) * Between(r, 0.03, 0.1) * c};
  } else if (f == "sensor_lag") {
    // Whole samples of the record; the truth's sensor emulator delays by at most 255 steps.
    const double sample_s = 1.0 / declared.controller.rate_Hz;
    const double most = std::floor(250.0 * 0.5 * declared.simulation.step_s / sample_s);
    t.values = {std::min(std::round(Between(r, 2.0, 8.0)), most) * sample_s,
                Between(r, 1e-4, 3e-4)};
  } else if (f == "tdb_drag_torque") {
    t.values = {Between(r, 1.0, 4.0)};
  } else if (f == "ribbon_dry_friction") {
    // A ribbon slipping softer than its catalogue stiffness (the declared Kelvin-Voigt one, the
    // search's top), hardening within its TDB's clearance (the search's top: 4 clearances).
    const double c = TdbOf(declared, e.name).clearance_m;
    const double kv = e.parameters[1].upper;
    t.declared = {0.0, kv, e.parameters[2].upper};
    t.values = {Between(r, 500.0, 2500.0), kv * Between(r, 0.03, 0.3), c * Between(r, 0.5, 1.5)};
  } else if (f == "ribbon_cross_coupling") {
    t.values = {Between(r, 0.3, 1.2)};
  } else {
    t.values = e.probe;  // an effect this battery does not know yet: at its probe
  }
  return t;
}

// The truth's record, with noise on currents, forces and speeds as the fit tests add it, and
// the declared rig fitted to it.
std::unique_ptr<FitResult> MakeAndFit(const ModelParams& truth, const ConfigVariants& declared,
                                      int threads, std::uint64_t seed) {
  MeasureOptions noise;
  noise.current_noise_A = 0.005;
  noise.force_noise_N = 2.0;
  noise.speed_noise_rad_s = 0.01;
  noise.seed = seed;
  const SyntheticMeasurement made = MakeMeasuredRecord(truth, noise);
  Keep(truth, made);
  FitRecordOptions options;
  options.rules.threads = threads;
  return FitRecord(declared, made.measurement, made.record, options);
}

struct Outcome {
  bool named = false, explained = false, recovered = false;
  std::string verdict, first, detail;
  double seconds = 0.0;
};

Outcome Run(const ConfigVariants& declared, const Effect& e, const Truth& truth, int threads,
            std::uint64_t seed) {
  ModelParams truth_params = WithEffects(declared, {&e}, {truth.values});
  truth_params.simulation.step_s = 0.5 * declared.declared().params.simulation.step_s;
  Outcome o;
  const auto start = std::chrono::steady_clock::now();
  try {
    const auto fit = MakeAndFit(truth_params, declared, threads, seed);
    const Selection& s = fit->selection;
    o.verdict = s.verdict;
    o.first = s.chosen.empty() ? "-" : s.chosen.front();
    o.named = o.first == e.name;
    o.explained = s.verdict == "explained";
    o.recovered = o.named;
    for (std::size_t i = 0; i < e.parameters.size(); ++i) {
      const EffectParameter& par = e.parameters[i];
      const ParameterEstimate* got = ChosenParameter(*fit, e.name, par.name);
      if (got == nullptr) {
        o.recovered = false;
        o.detail += fmt::format(" {}=? (truth {:.4g})", par.name, truth.values[i]);
        continue;
      }
      bool ok;
      if (par.periodic) {
        const double err = std::abs(std::remainder(got->value - truth.values[i], 2 * kPi));
        ok = err <= 0.35;
        o.detail += fmt::format(" {} {:.3g} vs {:.3g} ({:+.2f} rad)", par.name, got->value,
                                truth.values[i], err);
      } else {
        const double departure = std::abs(truth.values[i] - truth.declared[i]);
        const double err = std::abs(got->value - truth.values[i]) / departure;
        ok = err <= 0.2;
        o.detail += fmt::format(" {} {:.4g} vs {:.4g} ({:.0f} %)", par.name, got->value,
                                truth.values[i], 100.0 * err);
      }
      o.recovered = o.recovered && ok;
    }
    o.detail += fmt::format("  rms {:.3g} -> {:.3g}", s.rms_before, s.rms_after);
  } catch (const std::exception& ex) {
    o.verdict = "error";
    o.detail = ex.what();
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return o;
}

// Effects as an independent simulator may make them: library effects in another form (both
// TDBs offset, friction on one TDB, an unbalance off the library's plane, a pure delay...) and
// effects outside the library. `expect` lists the families a right answer names first; empty:
// the effect is not in the library, and a right answer is anything but "explained".
struct Variant {
  std::string name;
  std::vector<std::string> expect;
  std::function<void(ModelParams*, PortableRandom*)> make;
};

std::vector<Variant> Variants() {
  const auto offset = [](const TdbParams& t, PortableRandom* r) {
    return Sign(r) * Between(r, 0.15, 0.4) * t.clearance_m;
  };
  std::vector<Variant> v;
  v.push_back(
      {"both TDBs offset", {"tdb_misalignment"}, [offset](ModelParams* p, PortableRandom* r) {
         for (TdbParams& t : p->tdbs) t.misalignment = {true, offset(t, r), offset(t, r)};
       }});
  v.push_back(
      {"friction on one TDB", {"friction_coefficient"}, [](ModelParams* p, PortableRandom* r) {
         TdbParams& t = p->tdbs.front();
         const double f = Between(r, 0.4, 0.6);
         t.friction.coefficient *= f;
         t.ball_bearing().friction.kinetic_coefficient *= f;
         t.ball_bearing().friction.static_coefficient *= f;
       }});
  v.push_back({"unbalance at a TDB", {"unbalance"}, [](ModelParams* p, PortableRandom* r) {
                 UnbalanceParams u;
                 u.name = "truth";
                 u.position_m = p->tdbs.back().position_m;
                 u.mass_kg = 1.0;
                 u.eccentricity_m = Between(r, 2e-4, 6e-4);
                 u.phase_rad = Between(r, -kPi, kPi);
                 p->unbalances.push_back(u);
               }});
  v.push_back({"flux decay on one AMB", {"amb_flux_decay"}, [](ModelParams* p, PortableRandom* r) {
                 p->ambs.front().flux_decay = {true, Between(r, 3e-3, 1e-2)};
               }});
  v.push_back({"runout 1X and 2X", {"sensor_runout"}, [](ModelParams* p, PortableRandom* r) {
                 SensorParams& s = p->sensors.front();
                 const double c = p->tdbs.front().clearance_m;
                 s.runout = {true, Between(r, 0.04, 0.1) * c, Between(r, -kPi, kPi),
                             Between(r, 0.02, 0.04) * c, Between(r, -kPi, kPi)};
               }});
  v.push_back({"pure sensor delay", {"sensor_lag"}, [](ModelParams* p, PortableRandom* r) {
                 SensorParams& s = p->sensors.back();
                 s.lag = {true, std::round(Between(r, 3.0, 8.0)) / p->controller.rate_Hz, 0.0};
               }});
  v.push_back({"sensor offset only", {"sensor_gain_offset"}, [](ModelParams* p, PortableRandom* r) {
                 p->sensors.front().offset_m +=
                     Sign(r) * Between(r, 0.05, 0.1) * p->tdbs.front().clearance_m;
               }});
  v.push_back({"larger TDB clearance", {"tdb_clearance"}, [](ModelParams* p, PortableRandom* r) {
                 p->tdbs.front().clearance_m *= Between(r, 1.2, 1.4);
               }});
  v.push_back({"heavier rotor (outside)", {}, [](ModelParams* p, PortableRandom* r) {
                 const double f = Between(r, 1.05, 1.1);
                 p->rotor.rigid.mass_kg *= f;
                 for (ShaftSection& sec : p->rotor.sections) sec.material.density_kg_m3 *= f;
               }});
  v.push_back({"AMB current gain error (outside)", {}, [](ModelParams* p, PortableRandom* r) {
                 const double f = Between(r, 0.85, 0.92);
                 for (AmbParams& a : p->ambs) {
                   a.current_gain_N_per_A *= f;
                   a.stiffness_N_per_m *= f;
                 }
               }});
  return v;
}

bool IsIn(const std::vector<std::string>& list, const std::string& x) {
  return std::find(list.begin(), list.end(), x) != list.end();
}

std::string FamilyOf(const FitResult& fit, const std::string& effect) {
  for (const Effect& e : fit.library) {
    if (e.name == effect) return e.family;
  }
  return effect;
}

// One variant on one rig: true on a right answer.
bool RunVariant(const ConfigVariants& declared, const Variant& v, PortableRandom* random,
                int threads, std::uint64_t seed, const std::string& rig) {
  ModelParams truth = declared.declared().params;
  v.make(&truth, random);
  truth.simulation.step_s = 0.5 * declared.declared().params.simulation.step_s;
  const auto start = std::chrono::steady_clock::now();
  std::string verdict, chosen, detail;
  bool hit = false;
  try {
    const auto fit = MakeAndFit(truth, declared, threads, seed);
    const Selection& s = fit->selection;
    verdict = s.verdict;
    for (const std::string& c : s.chosen) chosen += (chosen.empty() ? "" : " + ") + c;
    if (v.expect.empty()) {
      hit = s.verdict != "explained";
    } else {
      hit = !s.chosen.empty() && IsIn(v.expect, FamilyOf(*fit, s.chosen.front())) &&
            (s.verdict == "explained" || s.verdict == "partly_explained");
    }
    for (const ParameterEstimate& p : s.chosen_fit.parameters) {
      detail += fmt::format(" {}={:.4g}", p.name, p.value);
    }
    detail += fmt::format("  rms {:.3g} -> {:.3g} (limit {:.3g})", s.rms_before, s.rms_after,
                          s.limit_after);
  } catch (const std::exception& ex) {
    verdict = "error";
    detail = ex.what();
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%-4s %03d %-36s %-32s %-17s %5.1f s %s;%s\n", hit ? "HIT" : "miss", g_case,
              rig.c_str(), v.name.c_str(), verdict.c_str(), seconds,
              chosen.empty() ? "-" : chosen.c_str(), detail.c_str());
  std::fflush(stdout);
  return hit;
}

std::vector<std::string> Split(const std::string& list) {
  std::vector<std::string> out;
  std::size_t from = 0;
  while (from <= list.size()) {
    const std::size_t comma = list.find(',', from);
    const std::string item = list.substr(from, comma == std::string::npos ? comma : comma - from);
    if (!item.empty()) out.push_back(item);
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  return out;
}

}  // namespace
}  // namespace ambdrop

int main(int argc, char** argv) {
  using namespace ambdrop;
  CLI::App app{"Hit rate of `ambdrop fit` over rigs x library effects at random strengths"};
  double lead_s = 0.05, after_s = 0.15;
  std::string rigs =
      "jarroux2019_industrial_pid.toml,jarroux2019_industrial_model2.toml,"
      "jarroux2016_rigid.toml,chen_itri_flexible.toml,ddcb_rigid.toml,metal_rubber_ring.toml";
  std::string only;
  std::uint64_t seed = 1;
  int threads = 2;
  app.add_option("--lead-s", lead_s, "Levitated time before the trigger (s)");
  app.add_option("--after-s", after_s, "Record length after the trigger (s)");
  app.add_option("--rigs", rigs, "Comma list of configs/ files");
  app.add_option("--only", only, "Only effects whose name contains this");
  app.add_option("--seed", seed, "Seed of the drawn strengths and of the noise");
  app.add_option("--threads", threads, "Fit threads");
  app.add_option("--keep", g_keep_dir, "Write each case's record (caseNNN.csv, .toml) here");
  bool variants = false;
  app.add_flag("--variants", variants,
               "Effects in other forms than the library's, and effects outside it");
  CLI11_PARSE(app, argc, argv);
  if (!g_keep_dir.empty()) std::filesystem::create_directories(g_keep_dir);

  PortableRandom random(seed);
  int cases = 0, hits = 0;
  for (const std::string& rig : Split(rigs)) {
    const ConfigVariants declared = testing::LoadTestVariants(
        rig, {fmt::format("trigger.enabled=true"), fmt::format("trigger.time_s={}", lead_s),
              fmt::format("simulation.duration_s={}", lead_s + after_s)});
    int rig_cases = 0, rig_hits = 0;
    if (variants) {
      for (const Variant& v : Variants()) {
        if (!only.empty() && v.name.find(only) == std::string::npos) continue;
        ++rig_cases;
        ++g_case;
        rig_hits += RunVariant(declared, v, &random, threads, seed, rig);
      }
    }
    const ModelParams& declared_params = declared.declared().params;
    for (const Effect& e : variants ? std::vector<Effect>{} : EffectLibrary(declared, true)) {
      const Truth truth = Draw(e, declared_params, &random);
      if (!only.empty() && e.name.find(only) == std::string::npos) continue;
      ++g_case;
      const Outcome o = Run(declared, e, truth, threads, seed);
      const bool hit = o.named && o.explained && o.recovered;
      ++rig_cases;
      rig_hits += hit;
      std::printf("%-4s %03d %-36s %-30s %-17s %5.1f s %s\n", hit ? "HIT" : "miss", g_case,
                  rig.c_str(), e.name.c_str(), o.verdict.c_str(), o.seconds,
                  (o.named ? o.detail : "named " + o.first + ";" + o.detail).c_str());
      std::fflush(stdout);
    }
    std::printf("== %s: %d of %d\n", rig.c_str(), rig_hits, rig_cases);
    cases += rig_cases;
    hits += rig_hits;
  }
  std::printf("== all: %d of %d hits (%.0f %%), %.2f s after the trigger\n", hits, cases,
              cases ? 100.0 * hits / cases : 0.0, after_s);
  return 0;
}

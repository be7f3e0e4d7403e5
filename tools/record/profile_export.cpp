#include "tools/record/profile_export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "controller_if/controller/current_profile.hpp"
#include "io/config/config_loader.hpp"
#include "io/config/profile_config.hpp"
#include "rt_core/limits.hpp"

namespace ambdrop {
namespace {

using AmbCurrents = std::array<std::array<double, 2>, kMaxAmbs>;

// The currents in force from each recorded step of the window on, timed from its start: those
// in force at `from` (the loop's start currents, or the last input before), then every input
// (a watchdog's zeroing is an input too). Inputs of one step: the last one holds.
CurrentSeries RecordedCurrents(const RecordedRun& run, int ambs, double dt, std::int64_t from,
                               std::int64_t to) {
  CurrentSeries series;
  series.ambs = ambs;
  AmbCurrents at_from = run.start.loop_current_A;
  const auto add = [&](std::int64_t step, const AmbCurrents& i) {
    const double t = static_cast<double>(step - from) * dt;
    if (!series.time_s.empty() && series.time_s.back() == t) {
      series.current_A.back() = i;
      return;
    }
    series.time_s.push_back(t);
    series.current_A.push_back(i);
  };
  bool started = false;
  for (const RecordedInput& in : run.inputs) {
    if (in.kind == RecordedInputKind::kWatchdogStop || in.step > to) break;
    const AmbCurrents i =
        in.kind == RecordedInputKind::kWatchdogZero ? AmbCurrents{} : in.current_A;
    if (in.step <= from) {
      at_from = i;
      continue;
    }
    if (!started) add(from, at_from);
    started = true;
    add(in.step, i);
  }
  if (!started) add(from, at_from);
  return series;
}

// The first failure and the restore after it, as a rig's [trigger] can say them.
TriggerParams RecordedTrigger(const RecordedRun& run, const ModelParams& params, double dt,
                              std::int64_t from, std::int64_t to, std::vector<std::string>* notes) {
  TriggerParams t;
  t.enabled = false;
  std::size_t used = 0;
  std::size_t outside = 0;
  for (std::size_t e = 0; e < run.power.size(); ++e) {
    const RecordedPower& p = run.power[e];
    if (p.step < from || p.step > to) {
      ++outside;
      continue;
    }
    const double time_s = static_cast<double>(p.step - from) * dt;
    if (!t.enabled && !p.event.restore) {
      t.enabled = true;
      t.time_s = time_s;
      t.axis_x = p.event.axis_x;
      t.axis_y = p.event.axis_y;
      for (std::size_t a = 0; a < params.ambs.size(); ++a) {
        if ((p.event.amb_mask & (1u << a)) != 0) t.ambs.push_back(params.ambs[a].name);
      }
      if (t.ambs.size() == params.ambs.size()) t.ambs.clear();
      ++used;
    } else if (t.enabled && p.event.restore && t.restore_time_s < 0.0) {
      t.restore_time_s = time_s;
      ++used;
    }
  }
  if (outside > 0) {
    notes->push_back(
        fmt::format("{} of the record's power events fall outside the window", outside));
  }
  if (used + outside < run.power.size()) {
    notes->push_back(fmt::format(
        "{} of the record's {} power events are not in [trigger] (it holds one failure and one "
        "restore); script them as scenario events",
        run.power.size() - used - outside, run.power.size()));
  }
  return t;
}

}  // namespace

ProfileExport ExportCurrentProfile(const RunRecordFile& record, const std::string& record_path,
                                   const ProfileWindow& window) {
  const LoadedConfig config =
      LoadConfigFromString(record.header.config_toml, record_path + " (recorded config)", {});
  const ModelParams& params = config.params;
  const double dt = params.simulation.step_s;
  const int ambs = static_cast<int>(params.ambs.size());
  if (ambs == 0) throw std::runtime_error(record_path + ": the recorded rig has no AMB");
  const std::size_t max_points = std::clamp<std::size_t>(window.max_points, 2, kMaxProfilePoints);
  // The record's end is bounded by its header; its config bounds it too.
  const std::int64_t end =
      std::min<std::int64_t>(record.run.end_step, std::llround(params.simulation.duration_s / dt));
  // Compared in steps as doubles first: llround is undefined beyond int64.
  const double end_steps = static_cast<double>(end) + 0.5;
  const bool inside = window.from_s >= 0.0 && window.from_s / dt < end_steps &&
                      (window.to_s < 0.0 || window.to_s / dt < end_steps);
  const std::int64_t from = inside ? std::llround(window.from_s / dt) : 0;
  const std::int64_t to = !inside || window.to_s < 0.0 ? end : std::llround(window.to_s / dt);
  if (!inside || from < 0 || to > end || to <= from) {
    throw std::runtime_error(fmt::format(
        "the profile window {} s to {} s is not inside the record, which covers 0 s to {} s",
        window.from_s, window.to_s < 0.0 ? end * dt : window.to_s, end * dt));
  }

  ProfileExport out;
  const CurrentSeries series = RecordedCurrents(record.run, ambs, dt, from, to);
  const ProfileDecimation kept = DecimateCurrents(series, max_points);
  out.recorded_samples = series.time_s.size();
  out.points = kept.kept.size();
  out.max_error_A = kept.max_error_A;

  ProfileConfig profile;
  profile.name = params.name + "_profile";
  profile.duration_s = static_cast<double>(to - from) * dt;
  for (const AmbParams& amb : params.ambs) profile.amb_names.push_back(amb.name);
  profile.ambs.resize(params.ambs.size());
  for (const std::size_t j : kept.kept) {
    for (int a = 0; a < ambs; ++a) {
      profile.ambs[a].push_back(
          {series.time_s[j], series.current_A[j][a][0], series.current_A[j][a][1]});
    }
  }
  profile.trigger = RecordedTrigger(record.run, params, dt, from, to, &out.notes);
  if (record.damaged) {
    out.notes.push_back(
        "the record is damaged: the profile covers only the part before the damage");
  }
  profile.header_comments = {
      fmt::format("Coil-current profiles exported by `ambdrop replay --export-profile` from {}",
                  record_path),
      fmt::format("(recorded by ambdrop {} from `{}`, config hash {}).",
                  record.header.ambdrop_version, record.header.source, record.header.config_hash),
      fmt::format("Window: record time {} s to {} s, here from 0 s.", from * dt, to * dt),
      fmt::format("{} recorded current samples kept as {} points per AMB; linear",
                  out.recorded_samples, out.points),
      fmt::format("interpolation between them is within {:.3g} A of every recorded sample.",
                  out.max_error_A),
      "Open loop: the currents no longer answer the sensors, so a current-driven AMB's negative",
      "stiffness lets small differences from the recorded run grow, as it would on the machine;",
      "the rotor starts at the equilibrium of the first currents, and the spin angle at 0.",
  };
  for (const std::string& n : out.notes) profile.header_comments.push_back("Note: " + n + ".");
  out.toml = ProfileConfigToml(config.effective_toml, profile);
  return out;
}

}  // namespace ambdrop

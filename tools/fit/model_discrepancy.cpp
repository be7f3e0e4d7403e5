#include "tools/fit/model_discrepancy.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "tools/fit/not_a_number.hpp"

namespace ambdrop {
namespace {

// Rows of the record with time in [from_s, to_s) where the model predicts a value.
struct Rows {
  std::size_t first = 0;
  std::size_t end = 0;
};
Rows RowsIn(const MeasuredRecord& r, double from_s, double to_s) {
  const auto lo = std::lower_bound(r.time_s.begin(), r.time_s.end(), from_s);
  const auto hi = std::lower_bound(lo, r.time_s.end(), to_s);
  return {static_cast<std::size_t>(lo - r.time_s.begin()),
          static_cast<std::size_t>(hi - r.time_s.begin())};
}

struct Pair {
  double record = kNaN;
  double model = kNaN;
};

// Least-squares slopes of record and model over the rows both have.
Pair Slopes(const MeasuredRecord& r, const std::vector<double>& v, const std::vector<double>& p,
            Rows rows) {
  double n = 0, st = 0, stt = 0, sv = 0, stv = 0, sp = 0, stp = 0;
  for (std::size_t j = rows.first; j < rows.end; ++j) {
    if (!std::isfinite(p[j]) || !std::isfinite(v[j])) continue;
    const double t = r.time_s[j] - r.time_s[rows.first];
    n += 1;
    st += t;
    stt += t * t;
    sv += v[j];
    stv += t * v[j];
    sp += p[j];
    stp += t * p[j];
  }
  const double det = n * stt - st * st;
  if (n < 3 || !(det > 0)) return {};
  return {(n * stv - st * sv) / det, (n * stp - st * sp) / det};
}

Pair Means(const std::vector<double>& v, const std::vector<double>& p, Rows rows) {
  double n = 0, sv = 0, sp = 0;
  for (std::size_t j = rows.first; j < rows.end; ++j) {
    if (!std::isfinite(p[j]) || !std::isfinite(v[j])) continue;
    n += 1;
    sv += v[j];
    sp += p[j];
  }
  if (n < 1) return {};
  return {sv / n, sp / n};
}

// RMS about the mean: how much a levitated channel moves.
Pair Spreads(const std::vector<double>& v, const std::vector<double>& p, Rows rows) {
  const Pair mean = Means(v, p, rows);
  double n = 0, sv = 0, sp = 0;
  for (std::size_t j = rows.first; j < rows.end; ++j) {
    if (!std::isfinite(p[j]) || !std::isfinite(v[j])) continue;
    n += 1;
    sv += (v[j] - mean.record) * (v[j] - mean.record);
    sp += (p[j] - mean.model) * (p[j] - mean.model);
  }
  if (n < 2) return {};
  return {std::sqrt(sv / n), std::sqrt(sp / n)};
}

// Seconds after rows.first when |x - x(first)| first reaches `travel` (NaN if never).
double Reaches(const MeasuredRecord& r, const std::vector<double>& x, Rows rows, double travel) {
  if (rows.first >= rows.end || !std::isfinite(x[rows.first])) return kNaN;
  for (std::size_t j = rows.first; j < rows.end; ++j) {
    if (std::isfinite(x[j]) && std::abs(x[j] - x[rows.first]) >= travel) {
      return r.time_s[j] - r.time_s[rows.first];
    }
  }
  return kNaN;
}

// Seconds after rows.first when |x| first falls to half of |x(first)|.
double HalfLife(const MeasuredRecord& r, const std::vector<double>& x, Rows rows) {
  if (rows.first >= rows.end || !std::isfinite(x[rows.first])) return kNaN;
  const double half = 0.5 * std::abs(x[rows.first]);
  for (std::size_t j = rows.first; j < rows.end; ++j) {
    if (std::isfinite(x[j]) && std::abs(x[j]) <= half) return r.time_s[j] - r.time_s[rows.first];
  }
  return kNaN;
}

std::string Times(double record, double model, const char* more, const char* less) {
  if (!(std::abs(model) > 0) || !std::isfinite(record / model)) return "differently from";
  const double ratio = std::abs(record / model);
  return ratio >= 1.0 ? fmt::format("{:.2g}x {} than", ratio, more)
                      : fmt::format("{:.2g}x {} than", 1.0 / ratio, less);
}

std::string Phase(const ChannelResidual& c) {
  const double before = std::isfinite(c.rms_before) ? c.rms_before : 0.0;
  const double impact = std::isfinite(c.rms_impact) ? c.rms_impact : 0.0;
  const double settled = std::isfinite(c.rms_settled) ? c.rms_settled : 0.0;
  if (before >= impact && before >= settled) return "levitated";
  return settled > impact ? "settled" : "drop";
}

}  // namespace

Discrepancy DescribeDiscrepancy(const ModelParams& params, const MeasurementParams& m,
                                const MeasuredRecord& r, const SimulatedRecord& model,
                                const ResidualReport& residual, const Selection& selection) {
  Discrepancy d;
  d.dominant = selection.verdict == "unexplained" || selection.verdict == "partly_explained" ||
               selection.unconfirmed_departure;
  std::size_t best = m.channels.size();
  for (std::size_t c = 0; c < residual.channels.size() && c < m.channels.size(); ++c) {
    const double share = residual.channels[c].cost_share;
    if (!std::isfinite(share) || m.Drives(m.channels[c])) continue;
    if (best == m.channels.size() || share > residual.channels[best].cost_share) best = c;
  }
  if (best == m.channels.size()) {
    d.dominant = false;
    return d;
  }
  const MeasurementChannel& ch = m.channels[best];
  const ChannelResidual& cr = residual.channels[best];
  const std::vector<double>& v = r.values[r.Column(ch.column)];
  const std::vector<double>& p = model.values[best];
  const FitWindows& w = residual.windows;
  d.channel = ch.column;
  d.description = cr.description;
  d.share = cr.cost_share;
  d.phase = Phase(cr);
  const Rows levitated = RowsIn(r, w.start_s, w.trigger_s);
  const Rows after = RowsIn(r, w.trigger_s, w.end_s + 1.0);
  const Rows drop = RowsIn(r, w.trigger_s, w.settled_start_s);
  const Rows settled = RowsIn(r, w.settled_start_s, w.end_s + 1.0);
  const auto set = [&](Pair x, std::string shape, std::vector<std::string> families) {
    d.record_value = x.record;
    d.model_value = x.model;
    d.shape = std::move(shape);
    d.key_families = std::move(families);
  };
  switch (ch.quantity) {
    case MeasuredQuantity::kRotorSpeed: {
      d.phase = "after_trigger";
      const Pair s = Slopes(r, v, p, after);
      set(s,
          fmt::format("after the trigger the rotor speed changes at {:.4g} rad/s^2, {} the "
                      "model's {:.4g} rad/s^2",
                      s.record, Times(s.record, s.model, "faster", "slower"), s.model),
          {"rotor.coast_down.* (constant, viscous, windage torques)", "tdb.*.friction.*",
           "tdb.*.spin.*", "rotor.materials.*.density_kg_m3 (the rotor's polar inertia)"});
      break;
    }
    case MeasuredQuantity::kTdbSpeed: {
      d.phase = "after_trigger";
      const Pair mean = Means(v, p, after);
      set(mean,
          fmt::format("after the trigger the race turns at {:.4g} rad/s on average, {} the "
                      "model's {:.4g} rad/s",
                      mean.record, Times(mean.record, mean.model, "faster", "slower"), mean.model),
          {"tdb.*.spin.inertia_kg_m2", "tdb.*.spin.rotational_damping_N_m_s",
           "tdb.*.spin.drag_torque_N_m", "tdb.*.inner_race_radius_m", "tdb.*.friction.*"});
      break;
    }
    case MeasuredQuantity::kDisplacement: {
      if (d.phase == "levitated") {
        const Pair s = Spreads(v, p, levitated);
        set(s,
            fmt::format("levitated, the reading moves by {:.3g} m RMS, {} the model's {:.3g} m",
                        s.record, Times(s.record, s.model, "more", "less"), s.model),
            {"unbalance.*", "sensor.*.runout.*", "sensor.*.noise.*", "[controller] gains",
             "amb.* force law (ki, ks)"});
      } else if (d.phase == "settled") {
        const Pair mean = Means(v, p, settled);
        set(mean,
            fmt::format("at rest the reading is {:.4g} m, the model's {:.4g} m ({:+.3g} m)",
                        mean.record, mean.model, mean.record - mean.model),
            {"tdb.*.clearance_m", "tdb.*.misalignment.*", "sensor.*.offset_m / gain",
             "tdb.*.position_m", "tdb.*.contact_law stiffness"});
      } else {
        const Pair rest = Means(v, p, settled);
        const double travel =
            0.5 *
            std::abs(rest.record - (std::isfinite(v[drop.first]) ? v[drop.first] : rest.record));
        const Pair t{Reaches(r, v, drop, travel), Reaches(r, p, drop, travel)};
        set(t,
            fmt::format("after the trigger the reading covers half its way to rest in {:.3g} s, "
                        "the model's in {:.3g} s",
                        t.record, t.model),
            {"amb.*.flux_decay.* (the power-loss law)", "amb.*.bias_source", "sensor.*.lag.*",
             "tdb.*.clearance_m", "measurement.power_loss = \"from_record\""});
      }
      break;
    }
    case MeasuredQuantity::kCurrent:
    case MeasuredQuantity::kControllerCommand: {
      if (d.phase == "levitated") {
        const Pair mean = Means(v, p, levitated);
        set(mean,
            fmt::format("levitated, the mean current is {:.4g} A, the model's {:.4g} A",
                        mean.record, mean.model),
            {"the rotor's weight (rotor.*, gravity)", "amb.*.electromagnet.* (k, gap, bias)",
             "amb.*.current_gain_N_per_A", "[controller] feedforward"});
      } else {
        const Pair t{HalfLife(r, v, after), HalfLife(r, p, after)};
        set(t,
            fmt::format("after the trigger the current halves in {:.3g} s, the model's in "
                        "{:.3g} s",
                        t.record, t.model),
            {"amb.*.flux_decay.* (the power-loss law)", "amb.*.bias_source",
             "[controller].amplifier", "measurement.power_loss = \"from_record\""});
      }
      break;
    }
    case MeasuredQuantity::kTdbNormalForce:
    case MeasuredQuantity::kTdbSupportForce: {
      if (d.phase == "settled") {
        const Pair mean = Means(v, p, settled);
        set(mean,
            fmt::format("at rest the force is {:.4g} N, the model's {:.4g} N", mean.record,
                        mean.model),
            {"the rotor's weight (rotor.*, gravity)", "tdb.*.position_m",
             "amb.*.flux_decay.* / bias_source (AMB force left at rest)"});
      } else {
        Pair peak{0.0, 0.0};
        for (std::size_t j = drop.first; j < drop.end; ++j) {
          if (std::isfinite(v[j])) peak.record = std::max(peak.record, std::abs(v[j]));
          if (std::isfinite(p[j])) peak.model = std::max(peak.model, std::abs(p[j]));
        }
        set(peak,
            fmt::format("during the drop the force peaks at {:.4g} N, {} the model's {:.4g} N",
                        peak.record, Times(peak.record, peak.model, "higher", "lower"), peak.model),
            {"tdb.*.contact_law.* (stiffness, damping)", "tdb.*.support / bearing stiffness",
             "the rotor's mass", "tdb.*.clearance_m"});
      }
      break;
    }
  }
  (void)params;
  return d;
}

std::vector<std::string> SharedDiscrepancies(const std::vector<RecordDiscrepancy>& records) {
  std::vector<std::string> out;
  if (records.size() < 2) return out;
  const std::size_t n = records.size();
  // The same channel and phase dominating, the model off in the same direction.
  std::map<std::tuple<std::string, std::string, int>, std::size_t> dominant;
  for (const RecordDiscrepancy& r : records) {
    const Discrepancy& d = r.discrepancy;
    if (!d.dominant) continue;
    const int sign = d.record_value > d.model_value ? 1 : d.record_value < d.model_value ? -1 : 0;
    ++dominant[{d.channel, d.phase, sign}];
  }
  for (const auto& [key, count] : dominant) {
    if (count != n) continue;
    const auto& [channel, phase, sign] = key;
    std::string families;
    for (const std::string& f : records.front().discrepancy.key_families) {
      families += (families.empty() ? "" : "; ") + f;
    }
    out.push_back(fmt::format(
        "every record leaves most of its residual on '{}' ({}), the record {} than the model "
        "there: a mismatch of the declared model, not of one drop; look at {}",
        channel, phase,
        sign > 0   ? "higher"
        : sign < 0 ? "lower"
                   : "no different",
        families));
  }
  // The same signature (kind, channel, sign) in every record.
  std::map<std::tuple<std::string, std::string, int>, std::size_t> signatures;
  std::map<std::tuple<std::string, std::string, int>, std::vector<std::string>> points;
  for (const RecordDiscrepancy& r : records) {
    std::set<std::tuple<std::string, std::string, int>> seen;
    for (const Signature& s : r.signatures) {
      const std::tuple<std::string, std::string, int> key{s.kind, s.channel, s.value > 0 ? 1 : -1};
      if (seen.insert(key).second) ++signatures[key];
      points[key] = s.points_to;
    }
  }
  for (const auto& [key, count] : signatures) {
    if (count != n) continue;
    const auto& [kind, channel, sign] = key;
    std::string to;
    for (const std::string& f : points[key]) to += (to.empty() ? "" : ", ") + f;
    out.push_back(
        fmt::format("every record's declared-model residual has a {} {} on '{}' "
                    "(points to {})",
                    sign > 0 ? "positive" : "negative", kind, channel, to));
  }
  // The same effect chosen on every record.
  std::map<std::string, std::size_t> chosen;
  for (const RecordDiscrepancy& r : records) {
    for (const std::string& e : std::set<std::string>(r.chosen.begin(), r.chosen.end())) {
      ++chosen[e];
    }
  }
  for (const auto& [effect, count] : chosen) {
    if (count == n) out.push_back(fmt::format("every record chose {}", effect));
  }
  return out;
}

}  // namespace ambdrop

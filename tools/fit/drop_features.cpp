#include "tools/fit/drop_features.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "rt_core/tdb_common.hpp"
#include "tools/fit/noise_floor.hpp"
#include "tools/fit/not_a_number.hpp"
#include "tools/fit/whirl_classifier.hpp"

namespace ambdrop {
namespace {

std::size_t RowAt(const MeasuredRecord& r, double t) {
  return static_cast<std::size_t>(std::lower_bound(r.time_s.begin(), r.time_s.end(), t) -
                                  r.time_s.begin());
}

double SettledFrom(const MeasuredRecord& r, double trigger_s) {
  return r.time_s.back() - std::min((r.time_s.back() - trigger_s) / 3.0, 0.1);
}

double Mean(const std::vector<double>& v, std::size_t first, std::size_t last) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t j = first; j < last && j < v.size(); ++j) {
    if (!std::isfinite(v[j])) continue;
    sum += v[j];
    ++n;
  }
  return n > 0 ? sum / static_cast<double>(n) : kNaN;
}

// Where a falling channel has gone 90 % of its way from the trigger to where it settles, and
// how far it then bounces back within 30 ms (the first rebound); NaN if it does not travel.
struct Fall {
  double time_s = kNaN;
  double rebound = kNaN;
};
Fall FallOf(const MeasuredRecord& r, const std::vector<double>& v, double trigger_s,
            double min_travel) {
  Fall f;
  const std::size_t t0 = RowAt(r, trigger_s);
  if (t0 >= v.size() || !std::isfinite(v[t0])) return f;
  const double settled = Mean(v, RowAt(r, SettledFrom(r, trigger_s)), v.size());
  const double way = settled - v[t0];
  if (!(std::abs(way) >= min_travel)) return f;
  for (std::size_t j = t0; j < v.size(); ++j) {
    if (std::isfinite(v[j]) && (v[j] - v[t0]) / way >= 0.9) {
      f.time_s = r.time_s[j];
      double back = 0.0;
      for (std::size_t k = j; k < v.size() && r.time_s[k] < r.time_s[j] + 0.03; ++k) {
        if (std::isfinite(v[k])) back = std::max(back, -(v[k] - settled) / way * std::abs(way));
      }
      f.rebound = back;
      return f;
    }
  }
  return f;
}

// The first time a TDB's surface reaches 95 % of the journal's surface speed after the trigger.
double SpinUp(const MeasuredRecord& r, const std::vector<double>& race, double trigger_s,
              double journal_speed_rad_s, const TdbParams& t) {
  const double ratio = t.journal_radius_m / InnerRaceRadius(t);
  for (std::size_t j = RowAt(r, trigger_s); j < race.size(); ++j) {
    if (std::isfinite(race[j]) && race[j] >= 0.95 * journal_speed_rad_s * ratio) {
      return r.time_s[j] - trigger_s;
    }
  }
  return kNaN;
}

// Synchronous component (amplitude) of v over rows [first, last) at `order` times the spin.
double Synchronous(const MeasuredRecord& r, const std::vector<double>& v, std::size_t first,
                   std::size_t last, double spin, int order) {
  double c = 0.0, s = 0.0;
  std::size_t n = 0;
  for (std::size_t j = first; j < last; ++j) {
    if (!std::isfinite(v[j])) continue;
    const double a = order * spin * r.time_s[j];
    c += v[j] * std::cos(a);
    s += v[j] * std::sin(a);
    ++n;
  }
  return n > 0 ? 2.0 * std::hypot(c, s) / static_cast<double>(n) : 0.0;
}

// The time constant of a fading signal: its integral over its value at the start.
double FadeTime(const MeasuredRecord& r, const std::vector<double>& v, std::size_t first) {
  if (first >= v.size() || !std::isfinite(v[first]) || std::abs(v[first]) < 1e-9) return 0.0;
  double area = 0.0;
  for (std::size_t j = first + 1; j < v.size(); ++j) {
    if (std::isfinite(v[j]) && std::isfinite(v[j - 1])) {
      area += 0.5 * (v[j] + v[j - 1]) * (r.time_s[j] - r.time_s[j - 1]);
    }
  }
  return area / v[first];
}

WhirlClassification Whirl(const MeasuredRecord& r, const std::vector<double>& x,
                          const std::vector<double>& y, std::size_t first, double spin,
                          double clearance) {
  std::vector<OrbitSample> orbit;
  for (std::size_t j = first; j < x.size(); ++j) {
    if (std::isfinite(x[j]) && std::isfinite(y[j]))
      orbit.push_back({r.time_s[j], x[j], y[j], spin});
  }
  return ClassifyWhirl(orbit, clearance);
}

}  // namespace

std::vector<FeatureComparison> CompareFeatures(const ModelParams& params,
                                               const MeasurementParams& m, const MeasuredRecord& r,
                                               const SimulatedRecord& model) {
  std::vector<FeatureComparison> out;
  const double trigger = model.trigger_time_s;
  const double clearance = params.tdbs.empty() ? 1e-3 : params.tdbs.front().clearance_m;
  const std::size_t settled = RowAt(r, SettledFrom(r, trigger));
  const double spin = params.simulation.spin_speed_rad_s;
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    const MeasurementChannel& ch = m.channels[c];
    if (m.Drives(ch)) continue;  // an input (from_record), never a residual
    const std::vector<double>& meas = r.values[r.Column(ch.column)];
    const std::vector<double>& sim = model.values[c];
    switch (ch.quantity) {
      case MeasuredQuantity::kDisplacement: {
        const Fall a = FallOf(r, meas, trigger, 0.25 * clearance);
        const Fall b = FallOf(r, sim, trigger, 0.25 * clearance);
        if (std::isfinite(a.time_s)) {
          out.push_back({"first_contact_s", ch.column, a.time_s - trigger, b.time_s - trigger});
          out.push_back({"first_rebound_m", ch.column, a.rebound, b.rebound});
        }
        out.push_back({"rest_position_m", ch.column, Mean(meas, settled, meas.size()),
                       Mean(sim, settled, sim.size())});
        break;
      }
      case MeasuredQuantity::kTdbNormalForce: {
        const std::size_t t0 = RowAt(r, trigger);
        double pm = 0.0, ps = 0.0;
        for (std::size_t j = t0; j < meas.size(); ++j) {
          pm = std::max(pm, meas[j]);
          if (std::isfinite(sim[j])) ps = std::max(ps, sim[j]);
        }
        out.push_back({"peak_load_N", ch.column, pm, ps});
        break;
      }
      case MeasuredQuantity::kTdbSpeed: {
        const TdbParams& t = params.tdbs[ch.index];
        out.push_back({"spin_up_s", ch.column, SpinUp(r, meas, trigger, spin, t),
                       SpinUp(r, sim, trigger, spin, t)});
        break;
      }
      default:
        break;
    }
  }
  for (const PlaneWhirl& w : ComparePlaneWhirls(params, m, r, model)) {
    out.push_back({std::string("whirl_ratio (") + WhirlName(w.record.kind) + " vs " +
                       WhirlName(w.model.kind) + ")",
                   w.plane, w.record.frequency_ratio, w.model.frequency_ratio});
  }
  return out;
}

std::vector<PlaneWhirl> ComparePlaneWhirls(const ModelParams& params, const MeasurementParams& m,
                                           const MeasuredRecord& r, const SimulatedRecord& model) {
  std::vector<PlaneWhirl> out;
  const double clearance = params.tdbs.empty() ? 1e-3 : params.tdbs.front().clearance_m;
  const std::size_t settled = RowAt(r, SettledFrom(r, model.trigger_time_s));
  const double spin = params.simulation.spin_speed_rad_s;
  // Over the settled phase.
  for (std::size_t s = 0; s < params.sensors.size(); ++s) {
    int cx = -1, cy = -1;
    for (std::size_t c = 0; c < m.channels.size(); ++c) {
      const MeasurementChannel& ch = m.channels[c];
      if (ch.quantity == MeasuredQuantity::kDisplacement && ch.index == static_cast<int>(s)) {
        (ch.axis == 0 ? cx : cy) = static_cast<int>(c);
      }
    }
    if (cx < 0 || cy < 0) continue;
    const auto& mx = r.values[r.Column(m.channels[cx].column)];
    const auto& my = r.values[r.Column(m.channels[cy].column)];
    out.push_back({params.sensors[s].name, Whirl(r, mx, my, settled, spin, clearance),
                   Whirl(r, model.values[cx], model.values[cy], settled, spin, clearance)});
  }
  return out;
}

std::vector<Signature> ResidualSignatures(const ModelParams& params, const MeasurementParams& m,
                                          const MeasuredRecord& r, const SimulatedRecord& model) {
  std::vector<Signature> out;
  const double trigger = model.trigger_time_s;
  const double spin = params.simulation.spin_speed_rad_s;
  const std::size_t first = model.first_row;
  const std::size_t trigger_row = RowAt(r, trigger);
  const std::size_t settled = RowAt(r, SettledFrom(r, trigger));
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    const MeasurementChannel& ch = m.channels[c];
    if (m.Drives(ch)) continue;  // an input (from_record), never a residual
    const std::vector<double>& meas = r.values[r.Column(ch.column)];
    const std::vector<double>& sim = model.values[c];
    std::vector<double> e(meas.size(), kNaN);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t j = first; j < meas.size(); ++j) {
      if (std::isfinite(sim[j])) e[j] = meas[j] - sim[j];
      lo = std::min(lo, meas[j]);
      hi = std::max(hi, meas[j]);
    }
    // A channel that carries only its noise (the coil currents of equivalent-law AMBs) has no
    // signature to read, only noise over noise; the cost leaves it out by the same rule.
    if (!(hi - lo > 10.0 * NoiseSigma(meas, first, meas.size()))) continue;
    const double range = hi - lo;
    const auto add = [&](const char* kind, double value, double relative,
                         std::vector<std::string> points_to) {
      if (std::abs(relative) >= 0.01) {
        out.push_back({kind, ch.column, value, relative, std::move(points_to)});
      }
    };
    if (ch.quantity == MeasuredQuantity::kDisplacement) {
      const double offset = Mean(e, settled, e.size());
      add("offset", offset, offset / range, {"tdb_misalignment", "sensor_gain_offset"});
      if (model.closed_loop && trigger_row > first + 10) {
        const double s1 = Synchronous(r, e, first, trigger_row, spin, 1);
        const double s2 = Synchronous(r, e, first, trigger_row, spin, 2);
        add("synchronous_1x", s1, s1 / range, {"sensor_runout", "unbalance"});
        add("synchronous_2x", s2, s2 / range, {"sensor_runout"});
      }
      // A lag: when the record passes half the model's fall, against when the model does (at a
      // depth both reach, so that a different rest position does not read as a lag).
      const Fall b = FallOf(r, sim, trigger, 0.25 * params.tdbs.front().clearance_m);
      if (std::isfinite(b.time_s) && trigger_row < meas.size()) {
        const double depth = 0.5 * (sim[RowAt(r, b.time_s)] - sim[trigger_row]) / 0.9;
        const auto passes = [&](const std::vector<double>& v) {
          for (std::size_t j = trigger_row; j < v.size(); ++j) {
            if (std::isfinite(v[j]) && (v[j] - v[trigger_row]) / depth >= 1.0) return r.time_s[j];
          }
          return kNaN;
        };
        const double lag = passes(meas) - passes(sim);
        if (std::isfinite(lag) && std::abs(lag) >= 2.0 * r.SampleInterval()) {
          add("lag", lag, lag / std::max(1e-3, b.time_s - trigger),
              {"sensor_lag", "amb_flux_decay", "tdb_misalignment"});
        }
      }
    }
    if (ch.quantity == MeasuredQuantity::kCurrent && trigger_row < meas.size()) {
      const double fade = FadeTime(r, meas, trigger_row) - FadeTime(r, sim, trigger_row);
      add("decay", fade, fade / 5e-3, {"amb_flux_decay"});
    }
    if (ch.quantity == MeasuredQuantity::kTdbSpeed ||
        ch.quantity == MeasuredQuantity::kRotorSpeed) {
      const double mean = Mean(e, trigger_row, e.size());
      std::vector<std::string> to = {"tdb_drag_torque", "friction_coefficient"};
      if (ch.quantity == MeasuredQuantity::kRotorSpeed) to.push_back("rotor_coast_down");
      add("offset", mean, mean / range, std::move(to));
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const Signature& a, const Signature& b) {
    return std::abs(a.relative) > std::abs(b.relative);
  });
  return out;
}

}  // namespace ambdrop

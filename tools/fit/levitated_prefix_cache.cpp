#include "tools/fit/levitated_prefix_cache.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace ambdrop {
namespace {

// A TDB whose journal reaches this share of its free radius counts as touching: the RK4 stages
// lie between the steps, and the reach's allowance for them is an estimate.
constexpr double kFreeShare = 0.9;

// Integrates TDB `tdb`'s own states alone over `steps` steps of `dt` from its initial state
// (a settled start's `settle_steps` first, then the run's from t = 0),
// with Simulator::Step's RK4 sums (rt_core/simulator.cpp; element by element, so each state
// comes out as in a whole run), the journal at the axis: free, its rates do not read it. False
// if the journal's reach leaves its free radius at any step. Fills `at_row` for the steps in
// `row_step`.
bool IntegrateFreeTdb(const TouchdownBearing& tdb, double dt, std::int64_t settle_steps,
                      std::int64_t steps, double reach_m, double spin_rad_s,
                      const std::vector<std::int64_t>& row_step, ResumedTdb* out) {
  const int size = tdb.StateSize();
  Eigen::VectorXd y(size), k1(size), k2(size), k3(size), k4(size), stage(size);
  tdb.InitialState(y.data());
  const JournalMotion centred{0.0, 0.0, 0.0, 0.0, spin_rad_s};
  TdbForce force;
  const auto free = [&](const Eigen::VectorXd& s) {
    return JournalFree(reach_m, tdb.FreeRadius_m(s.data()));
  };
  if (!free(y)) return false;
  // A TDB at rest (every rate zero) keeps its initial state: no need to step it.
  tdb.Evaluate(centred, y.data(), k1.data(), &force);
  const bool at_rest = (k1.array() == 0.0).all();
  out->at_row.assign(row_step.size(), TdbForce{});
  std::size_t next_row = 0;
  // Rows by step from t = 0 (row_step rises with the row; -1: none).
  const auto report_rows = [&](std::int64_t k) {
    while (next_row < row_step.size() && row_step[next_row] <= k) {
      if (row_step[next_row] == k && k >= 0) {
        tdb.Evaluate(centred, y.data(), k1.data(), &out->at_row[next_row]);
      }
      ++next_row;
    }
  };
  const double half_h = 0.5 * dt;
  const double sixth_h = dt / 6.0;
  for (std::int64_t k = -settle_steps; k < steps; ++k) {
    if (k >= 0) report_rows(k);
    if (at_rest) continue;
    tdb.Evaluate(centred, y.data(), k1.data(), &force);
    stage = y + half_h * k1;
    tdb.Evaluate(centred, stage.data(), k2.data(), &force);
    stage = y + half_h * k2;
    tdb.Evaluate(centred, stage.data(), k3.data(), &force);
    stage = y + dt * k3;
    tdb.Evaluate(centred, stage.data(), k4.data(), &force);
    y += sixth_h * (((k2 + k3) * 2.0 + k1) + k4);
    if (!y.allFinite() || !free(y)) return false;
  }
  out->state = y;
  return true;
}

// Whether the run of `a` repeats the levitated time of `cached` but for TDBs `differ` says
// differ (every other number equal, or acting only after the power loss).
bool SameLevitatedTime(ModelParams a, const LevitatedPrefix& cached, std::vector<bool>* differ) {
  const ModelParams& b = cached.params;
  // The run's length, the power-loss laws and the coast-down act from the trigger on.
  a.simulation.duration_s = b.simulation.duration_s;
  a.rotor.coast_down = b.rotor.coast_down;
  if (a.ambs.size() != b.ambs.size() || a.tdbs.size() != b.tdbs.size()) return false;
  for (std::size_t i = 0; i < a.ambs.size(); ++i) a.ambs[i].flux_decay = b.ambs[i].flux_decay;
  differ->assign(a.tdbs.size(), false);
  for (std::size_t i = 0; i < a.tdbs.size(); ++i) {
    if (a.tdbs[i] == b.tdbs[i]) continue;
    // The journal's reach was measured at the cached TDB's station.
    if (!cached.tdb_free[i] || a.tdbs[i].position_m != b.tdbs[i].position_m) return false;
    (*differ)[i] = true;
    a.tdbs[i] = b.tdbs[i];
  }
  return a == b;
}

}  // namespace

bool JournalFree(double reach_m, double free_radius_m) {
  return reach_m < kFreeShare * free_radius_m;
}

std::uint64_t RecordFingerprint(const MeasuredRecord& record) {
  // FNV-1a over the values' bits, word by word, in four interleaved lanes (one lane's chain of
  // multiplies was 4 % of a fit), the lanes folded at the end.
  constexpr std::uint64_t kPrime = 1099511628211ull;
  std::array<std::uint64_t, 4> lane = {1469598103934665603ull, 1ull, 2ull, 3ull};
  const auto mix = [&lane](const std::vector<double>& v) {
    std::size_t k = 0;
    for (; k + 4 <= v.size(); k += 4) {
      for (std::size_t l = 0; l < 4; ++l) {
        lane[l] = (lane[l] ^ std::bit_cast<std::uint64_t>(v[k + l])) * kPrime;
      }
    }
    for (; k < v.size(); ++k) lane[0] = (lane[0] ^ std::bit_cast<std::uint64_t>(v[k])) * kPrime;
    lane[1] = (lane[1] ^ v.size()) * kPrime;
  };
  mix(record.time_s);
  for (const std::vector<double>& column : record.values) mix(column);
  std::uint64_t h = 1469598103934665603ull;
  for (const std::uint64_t l : lane) h = (h ^ l) * kPrime;
  return h;
}

std::optional<PrefixMatch> LevitatedPrefixCache::Find(const ModelParams& params, const Model& model,
                                                      const MeasurementParams& m,
                                                      std::uint64_t record_fingerprint,
                                                      bool keep_states) {
  std::vector<std::shared_ptr<const LevitatedPrefix>> entries;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    entries = entries_;
  }
  std::vector<bool> differ;
  for (auto e = entries.rbegin(); e != entries.rend(); ++e) {
    const LevitatedPrefix& p = **e;
    if (p.record_fingerprint != record_fingerprint || p.keep_states != keep_states ||
        !(p.measurement == m) || !SameLevitatedTime(params, p, &differ)) {
      continue;
    }
    PrefixMatch match;
    match.prefix = *e;
    match.tdbs.resize(model.tdbs.size());
    const int n = model.modes();
    const double spin = p.driver.state.y(2 * n);
    bool resumable = true;
    for (std::size_t i = 0; i < model.tdbs.size() && resumable; ++i) {
      ResumedTdb& t = match.tdbs[i];
      t.changed = differ[i];
      if (!t.changed) {
        // The same TDB in the same layout: its states are the cached run's.
        t.state = p.driver.state.y.segment(p.tdb_state_offset[i], model.tdbs[i]->StateSize());
        continue;
      }
      resumable = IntegrateFreeTdb(*model.tdbs[i], model.params.simulation.step_s, p.settle_steps,
                                   p.steps, p.journal_reach_m[i], spin, p.row_step, &t);
    }
    if (!resumable) continue;
    std::lock_guard<std::mutex> lock(mutex_);
    ++hits_;
    return match;
  }
  return std::nullopt;
}

void LevitatedPrefixCache::Insert(std::shared_ptr<const LevitatedPrefix> prefix) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (entries_.size() >= kCapacity) entries_.erase(entries_.begin());
  entries_.push_back(std::move(prefix));
}

std::int64_t LevitatedPrefixCache::hits() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return hits_;
}

}  // namespace ambdrop

#pragma once
// A fit runs its model from the record's start in every closed-loop run, though most of its
// candidates (a TDB's friction, clearance or offset, a power-loss law, a coast-down loss) act
// only once the power fails: up to the trigger those runs repeat the declared model's, step for
// step. This cache keeps a run's levitated time (everything the run carries at the start of the
// trigger's step) and resumes later runs from it when their levitated time would repeat it bit
// for bit:
//   - the models agree in every number but those that act only after the power loss (the AMBs'
//     flux decay, the rotor's coast-down) and the TDBs';
//   - a TDB that differs touched nothing in either model: the journal stayed within what its
//     free radius (TouchdownBearing::FreeRadius_m) allows, with room to spare, so its forces
//     on the rotor were zero and its rates did not read the journal. Its own states (races
//     settling under their weight) are integrated alone with the simulator's RK4 sums, which
//     are element by element, so they come out as in a whole run.
// A settled start's steps count as the prefix's. The record, its [measurement] table and the
// run's options that act before the trigger are part of the comparison. A resumed run is bit for
// bit the run it replaces (tests hold it).
#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "controller_if/boundary/sensor_emulator.hpp"
#include "controller_if/controller/pid_controller.hpp"
#include "controller_if/loop/step_driver.hpp"
#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "rt_core/model.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop {

/// One closed-loop run on a record up to the start of its trigger's step.
struct LevitatedPrefix {
  ModelParams params;  ///< as the run built its model
  MeasurementParams measurement;
  std::uint64_t record_fingerprint = 0;
  bool keep_states = false;
  /// Per TDB: whether the journal stayed well inside its free radius over the whole prefix,
  /// a settled start's steps included.
  std::array<bool, kMaxTdbs> tdb_free{};
  /// Per TDB: the journal's largest reach from the machine axis over the prefix's steps, its
  /// distance plus twice its speed times the step (where the RK4 stages may take it).
  std::array<double, kMaxTdbs> journal_reach_m{};
  std::int64_t settle_steps = 0;  ///< steps of a settled start (simulation.settle_s) before t = 0
  std::int64_t steps = 0;         ///< steps from t = 0 to the trigger (its step index)
  std::vector<int> tdb_state_offset;  ///< the cached model's layout of State::y

  StepDriver::Snapshot driver;
  std::optional<ReferenceController> controller;
  std::optional<SensorEmulator> record_sensors;
  ControlInput input;
  AxisCurrents command{};
  std::size_t row = 0;                      ///< the next record row to predict
  std::size_t rows = 0;                     ///< rows predicted so far
  std::vector<std::vector<double>> values;  ///< [channel][row], rows before `row`
  std::vector<Eigen::VectorXd> states;      ///< keep_states only, rows before `row`
  std::vector<double> model_tare;
  /// The step each row before `row` was predicted at (-1: none).
  std::vector<std::int64_t> row_step;
};

/// A TDB's states at the end of a resumed prefix and what it reported at the prefix's rows.
struct ResumedTdb {
  bool changed = false;  ///< differs from the cached run's TDB
  Eigen::VectorXd state;
  std::vector<TdbForce> at_row;  ///< changed TDBs: by row (rows without a step: default)
};

/// What a later run takes from the cache.
struct PrefixMatch {
  std::shared_ptr<const LevitatedPrefix> prefix;
  std::vector<ResumedTdb> tdbs;  ///< by the later model's TDB
};

/// Whether a journal whose reach from the machine axis is `reach_m` stays clear of a TDB of
/// free radius `free_radius_m` with room to spare for the RK4 stages between the steps.
bool JournalFree(double reach_m, double free_radius_m);

/// A content fingerprint of a record (time column and values), so that an entry made on one
/// record is never taken for another.
std::uint64_t RecordFingerprint(const MeasuredRecord& record);

/// Shared by the runs of one fit, from several threads.
class LevitatedPrefixCache {
 public:
  /// An entry whose levitated time the run of `params` (its model `model`) repeats bit for bit,
  /// with its TDBs' states and row outputs for `model`; empty if none.
  std::optional<PrefixMatch> Find(const ModelParams& params, const Model& model,
                                  const MeasurementParams& m, std::uint64_t record_fingerprint,
                                  bool keep_states);
  void Insert(std::shared_ptr<const LevitatedPrefix> prefix);
  /// Runs resumed so far (for tests and the report of a fit's work).
  std::int64_t hits() const;

 private:
  // A fit alternates between a few levitated behaviours: the declared model's and its jitter
  // draws' (up to 64 noise seeds), a sensor or AMB candidate's: the most recent last.
  static constexpr std::size_t kCapacity = 96;
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<const LevitatedPrefix>> entries_;
  std::int64_t hits_ = 0;
};

}  // namespace ambdrop

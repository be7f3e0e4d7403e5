#pragma once
// An ambdrop run record (`--record FILE.lcm` on sim, hil and scenario runs; read by
// tools/record/run_record_reader.hpp) as a measured record for `ambdrop fit`: the rows are the
// sensor samples the run sent, the columns are named as `ambdrop measure` names them
// (tools/fit/measured_record_maker.hpp), and the [measurement] table that describes them comes
// with it.
#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "rt_core/model_params.hpp"
#include "tools/record/run_record_reader.hpp"

namespace ambdrop {

struct RecordAsMeasurement {
  MeasuredRecord record;
  MeasurementParams measurement;  ///< one channel per record column, in column order
};

/// One row per sensor sample, at its time (the controller's rate), with the columns:
/// - x_<sensor>, y_<sensor>: the readings sent, as sent;
/// - i_<amb>_x, i_<amb>_y: the coil control current in force at the row: the last input applied
///   from the row's step or earlier (a watchdog's zeroing input zeroes it); after an axis loses
///   power, the current it held then falling by the AMB's power-loss law (ReportedCoilCurrent,
///   tools/fit/current_sampler.hpp, as `ambdrop measure` reads it);
/// - f_<tdb>, w_<tdb>, w_rotor: TDB normal force, inner-race speed and rotor spin speed from the
///   last state event at or before the row (the first one for rows before it); left out when
///   the record holds no state events.
/// measurement.trigger_time_s is the first power failure's step times the record's step (with
/// none, trigger = "detect"); sample_rate_Hz is that of the sensor period (the smallest step gap
/// between samples). `params` is the recorded rig (its header's config): it names the columns
/// and gives the flux decay the currents followed. Throws std::invalid_argument when the record
/// cannot be read so: fewer than two sensor samples (a run without a controller sends none),
/// state events for another number of TDBs, two columns of one name.
/// `with_commands` adds cmd_<amb>_x, cmd_<amb>_y after the other columns: the controller's
/// commanded currents (the last input applied from the row's step or earlier), which go on
/// after power loss where the coil currents fade.
RecordAsMeasurement MeasurementFromRunRecord(const RunRecordFile& file, const ModelParams& params,
                                             bool with_commands = false);

}  // namespace ambdrop

#pragma once
// The [measurement] table: how the columns of a measured record (io/files/measured_csv.hpp) map
// onto the model's quantities, for `ambdrop fit`. Example:
//
//   [measurement]
//   sample_rate_Hz = 20000.0        # the record's; its time column is checked against it
//   trigger_time_s = 0.2            # or: trigger = "detect" (tools/fit/record_trigger_detect.hpp)
//   time_column = "time_ms"         # default "t"; the record's first column
//   time_unit = "ms"                # default "s"; or "us"
//   power_loss = "from_record"      # default "declared": the coil-current channels drive the
//                                   #   AMBs through and after the trigger (not compared)
//   [[measurement.channel]]
//   column = "x_de"                 # header name in the CSV
//   quantity = "displacement"       # displacement | current | controller_command |
//   sensor = "de"                   #   tdb_normal_force | tdb_support_force | tdb_speed |
//   axis = "x"                      #   rotor_speed
//   unit = "um"                     # or scale = 1e-6 (SI per record unit); default SI
//   window = "after_trigger"        # all (default) | before_trigger | after_trigger
//   from_s = 0.0                    # and/or to_s: compared only from/to these seconds
//                                   #   relative to the trigger
//
// displacement: sensor + axis (m, the sensor's reading); current: amb + axis (A, the coil's
// control current, fading after power loss); controller_command: amb + axis (A, what the
// controller outputs, which keeps running after power loss); tdb_normal_force: tdb (N);
// tdb_support_force: tdb + axis (N, a load cell under the TDB, tared by its reading before the
// trigger); tdb_speed: tdb (rad/s, inner race); rotor_speed (rad/s).
//
// Units (`unit`, checked against the quantity's dimension): length m, mm, um (or µm); current
// A, mA; force N, kN; speed rad/s, rpm, Hz or rev/s (revolutions per second); time s, ms, us.
// The record is converted to SI once, when read (io/files/measured_record_si.hpp).
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rt_core/model_params.hpp"

namespace ambdrop {

// Declared, not included: io/config/config_loader.hpp includes this header, and toml++ (which
// io/config/toml_reader.hpp brings) must stay inside io, the one target built with its library
// flags.
namespace config_detail {
class TableReader;
}  // namespace config_detail

enum class MeasuredQuantity {
  kDisplacement,
  kCurrent,
  kTdbNormalForce,
  kTdbSpeed,
  kRotorSpeed,
  kControllerCommand,
  kTdbSupportForce,
};

/// Where along the record a channel is compared, relative to the trigger.
enum class ChannelWindow {
  kAll,
  kBeforeTrigger,  ///< record times before the trigger
  kAfterTrigger,   ///< record times at or after the trigger
};

/// The config spelling of a quantity: "displacement", "current", "tdb_normal_force", ...
std::string_view MeasuredQuantityName(MeasuredQuantity quantity);

struct MeasurementChannel {
  std::string column;  ///< CSV header name
  MeasuredQuantity quantity = MeasuredQuantity::kDisplacement;
  int index = -1;  ///< sensor, AMB or TDB index in the model's order; -1 for rotor_speed
  int axis = -1;   ///< 0 = x, 1 = y for quantities with an axis; -1 otherwise
  /// SI per record unit: the column is multiplied by it when read (1 for SI columns).
  double scale = 1.0;
  std::string unit{};  ///< the `unit` spelling it came from; empty for SI or a given `scale`
  ChannelWindow window = ChannelWindow::kAll;
  /// Compared only at record times t with trigger + from_s <= t < trigger + to_s.
  std::optional<double> from_s{};
  std::optional<double> to_s{};

  std::string Describe(const ModelParams& params) const;  ///< "displacement de x"
  /// Whether record time `t_s` lies inside the channel's window for a trigger at `trigger_s`.
  bool InWindow(double t_s, double trigger_s) const;
  /// Whether the channel is compared over only part of the record.
  bool Windowed() const { return window != ChannelWindow::kAll || from_s || to_s; }
  /// The window in words, for messages: "after the trigger, from 0.01 s".
  std::string DescribeWindow() const;
  static MeasurementChannel Of(std::string column, MeasuredQuantity quantity, int index, int axis) {
    MeasurementChannel c;
    c.column = std::move(column);
    c.quantity = quantity;
    c.index = index;
    c.axis = axis;
    return c;
  }
  friend bool operator==(const MeasurementChannel&, const MeasurementChannel&) = default;
};

/// The quantity's SI unit ("m", "A", "N", "rad/s").
std::string_view MeasuredQuantitySiUnit(MeasuredQuantity quantity);

/// SI per unit of a `unit` spelling for `quantity` (1e-6 for "um" on a displacement); empty if
/// the spelling is not one of that quantity's dimension.
std::optional<double> MeasurementUnitScale(MeasuredQuantity quantity, std::string_view unit);

/// Seconds per unit of a `time_unit` spelling ("s", "ms", "us"); empty for any other.
std::optional<double> TimeUnitScale(std::string_view unit);

/// "x" for axis 0, "y" otherwise: the axis as column names and the [measurement] table spell it.
inline const char* MeasurementAxisName(int axis) {
  return axis == 0 ? "x" : "y";
}

/// What drives the AMBs' coil currents after the trigger in `ambdrop fit`.
enum class PowerLossSource {
  kDeclared,    ///< the declared power-loss law (amb.NAME.flux_decay), from the held current
  kFromRecord,  ///< the record's coil-current channels, through and after the trigger
};

struct MeasurementParams {
  double sample_rate_Hz = 0.0;    ///< of the record, checked against its time column in SI
  std::string time_column = "t";  ///< the record's first column
  std::string time_unit = "s";    ///< its unit, as spelled
  double time_scale_s = 1.0;      ///< seconds per record time unit
  /// The time power failed, in record time; empty with detect_trigger.
  std::optional<double> trigger_time_s;
  bool detect_trigger = false;
  std::vector<MeasurementChannel> channels;  ///< in the config's order; columns are unique
  /// `power_loss = "from_record"`: the coil-current channels drive the model from the run's
  /// start to its end (open loop), so the power-loss law of their axes is not the model's to
  /// predict and those channels are inputs, never compared. A controller-command channel never
  /// drives after the trigger (it keeps answering the falling rotor, the coil does not).
  PowerLossSource power_loss = PowerLossSource::kDeclared;
  /// `trigger_state = "record"`: the rotor's state at the trigger is fitted, through the model
  /// driven by the measured currents, to a lead window of the displacement samples before it
  /// (tools/fit/lead_state_estimate.hpp); closed loop the window starts from the model's own
  /// levitated state, open loop from the local fit at the window's start. The record's noise
  /// moves a levitated rotor by more than any model predicts sample by sample, and a rotor that
  /// the power loss leaves unstable (a magnet's bias, whose negative stiffness stays) goes where
  /// that motion sends it. "model" (default): closed loop the model's own levitated state, open
  /// loop a quadratic through each channel's samples around the run's start.
  bool trigger_state_from_record = false;
  /// "record_start": the drop's start only (the fit's early part) from the lead window's
  /// estimate, as "record"; the rest of the record from the model's own levitated state. The
  /// start is deterministic given the state at the trigger, which the record tells; after the
  /// first impacts a drop may be chaotic, and there the model's state and draws of its jitter
  /// compare (docs/fit.md). trigger_state_from_record stays false: the fit's cost of the start
  /// sets it for its own runs (tools/fit/record_cost.hpp, MeasurementFor).
  bool trigger_state_for_start = false;
  /// Whether channel `ch` is an input (a from_record coil current), not compared.
  bool Drives(const MeasurementChannel& ch) const {
    return power_loss == PowerLossSource::kFromRecord && ch.quantity == MeasuredQuantity::kCurrent;
  }
  friend bool operator==(const MeasurementParams&, const MeasurementParams&) = default;
};

namespace config_detail {
/// Reads [measurement] strictly (unknown keys, unknown sensor/AMB/TDB names, a key that the
/// quantity does not take, a duplicate column, neither or both of trigger_time_s and trigger,
/// a unit of another dimension, both unit and scale, a zero scale, an empty window: each a
/// ConfigError naming file, line and key).
MeasurementParams ReadMeasurement(const TableReader& table, const ModelParams& params);
}  // namespace config_detail

}  // namespace ambdrop

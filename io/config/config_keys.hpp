#pragma once
// The registry of a config's keys: every number the readers took from a config (or defaulted),
// with its dotted path (exactly what `--set` accepts), its unit (from the key's name), its class
// and the range the readers accept. The fit draws its "the declared value is off" candidates from
// the physical keys; `ambdrop keys` prints the registry for whoever translates a rig sheet.
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace ambdrop {

/// What a key describes, which decides whether a fit may move it.
enum class KeyClass {
  kPhysical,     ///< the machine: rotor, bearings, AMBs, sensors' geometry and gains, TDBs
  kMeasurement,  ///< how it is observed: noise, quantisation, seeds, the record's columns
  kSolver,       ///< how it is computed: step, duration, output interval, controller rate
  kRun,          ///< what happens in the run: trigger and scenario times
  kInterface,    ///< how it talks: CAN frames, real-time scheduling
};

const char* KeyClassName(KeyClass key_class) noexcept;

struct ConfigKey {
  std::string path;  ///< "tdb.de.clearance_m", "rotor.sections[2].length_m"
  std::string unit;  ///< "m", "N s/m"; "" for a dimensionless key
  KeyClass key_class = KeyClass::kPhysical;
  double value = 0.0;    ///< as read, or the default the reader used
  bool declared = true;  ///< false: absent from the config, the reader's default applies
  /// true: the readers take a whole number only (TableReader::Integer), so an override must be
  /// written without a decimal point (OverrideInteger); lower and upper are whole numbers.
  bool integer = false;
  double lower = -std::numeric_limits<double>::infinity();  ///< the readers' accepted range
  double upper = std::numeric_limits<double>::infinity();
  bool lower_inclusive = true;
  bool upper_inclusive = true;
  std::string location;  ///< "FILE:LINE" or "--set ..."; "" for a default
  /// false: its table is switched off (`enabled = false` beside it), so the model does not use
  /// it until the table is switched on.
  bool in_force = true;
};

/// The unit a key's name carries ("m" for "clearance_m", "Hz" for "cutoff_Hz"), "" if none.
std::string KeyUnit(std::string_view key);

/// The class of a key from its dotted path (rules in config_keys.cpp).
KeyClass ClassOfKey(std::string_view path);

/// A range a fit may search for a key "whose declared value is off": relative to the declared
/// value (a factor of 2 either way for a size, a span either side for a signed quantity, 10 %
/// or 1 cm either side for a station along the shaft), or, for a key declared 0, a physical
/// span by unit class; always inside the readers' range. An integer key's ends are whole
/// numbers: from half to twice a positive count, else two either side.
struct FitRange {
  double lower = 0.0;
  double upper = 0.0;
};
FitRange DefaultFitRange(const ConfigKey& key);
/// The same with the config's other keys known: a station along the shaft (`position_m`,
/// `centre_of_mass_m`) may then be anywhere up to nine tenths of the way to its neighbouring
/// stations (the other items' stations in force, those within a millimetre of it aside; beyond
/// the last one, as far as the gap on its other side), and no further than a tenth of the span
/// of all stations either way; with no neighbour, the range above.
FitRange DefaultFitRange(const ConfigKey& key, const std::vector<ConfigKey>& keys);

/// true for a station along the shaft: a key `...position_m` or `...centre_of_mass_m` in metres.
bool IsStationKey(const ConfigKey& key);

/// The key with this path among `keys`; nullptr if no reader took it.
const ConfigKey* FindKey(const std::vector<ConfigKey>& keys, std::string_view path);

/// The keys a load recorded, in the order read; a key read twice is kept once (the last read).
class KeyLog {
 public:
  void Record(ConfigKey key);
  const std::vector<ConfigKey>& keys() const { return keys_; }
  std::vector<ConfigKey> Take() { return std::move(keys_); }

 private:
  std::vector<ConfigKey> keys_;
};

}  // namespace ambdrop

#pragma once
// Step b/c of `ambdrop fit`: the drop's features, read the same way from the record and from
// the model (first contact, peak loads, first rebound, spin-up times, rest position, whirl),
// and the residual's signatures (offset, synchronous 1X/2X content while levitated, the fade of
// the currents after power loss, a time lag, the whirl's direction), each with the effects it
// points to. The signatures rank the candidates the fit then tries; the fit decides.
#include <string>
#include <vector>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "tools/fit/simulate_on_record.hpp"
#include "tools/fit/whirl_classifier.hpp"

namespace ambdrop {

struct FeatureComparison {
  std::string feature;  ///< "first_contact_s", "peak_load_N", "first_rebound_m", ...
  std::string channel;  ///< the column it is read from ("" for the record as a whole)
  double measured = 0.0;
  double model = 0.0;  ///< NaN where the model's run does not show it
};

struct Signature {
  std::string kind;       ///< "offset", "synchronous_1x", "synchronous_2x", "decay", "lag", "whirl"
  std::string channel;    ///< the column (or sensor plane for whirl)
  double value = 0.0;     ///< SI: m, m, m, s (measured tau - model tau), s, whirl ratio difference
  double relative = 0.0;  ///< against the channel's measured range (or 0 where not meaningful)
  std::vector<std::string> points_to;  ///< effect families it suggests
};

/// The drop's features from the record and from the model's prediction of it.
std::vector<FeatureComparison> CompareFeatures(const ModelParams& params,
                                               const MeasurementParams& measurement,
                                               const MeasuredRecord& record,
                                               const SimulatedRecord& model);

/// The whirl at one sensor plane with both axes measured, after the drop settles: the
/// record's and the model's (Jarroux 2016, seed 001, Sec. 3).
struct PlaneWhirl {
  std::string plane;  ///< the sensor's name
  WhirlClassification record;
  WhirlClassification model;
};
std::vector<PlaneWhirl> ComparePlaneWhirls(const ModelParams& params,
                                           const MeasurementParams& measurement,
                                           const MeasuredRecord& record,
                                           const SimulatedRecord& model);

/// The residual's signatures that stand out (above 1 % of a channel's range, or a clear lag,
/// decay or whirl difference), largest first.
std::vector<Signature> ResidualSignatures(const ModelParams& params,
                                          const MeasurementParams& measurement,
                                          const MeasuredRecord& record,
                                          const SimulatedRecord& model);

}  // namespace ambdrop

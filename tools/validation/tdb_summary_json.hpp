#pragma once
#include "io/files/json_writer.hpp"
#include "tools/validation/run_summary.hpp"

namespace ambdrop {

/// Writes `"tdbs": {NAME: {peak_normal_force_N, max_excursion_over_clearance,
/// first_contact_time_s, spinup_time_s, whirl, whirl_frequency_ratio}, ...}` into an open JSON
/// object (sim and hil summaries). `whirl` is "rocking", "backward_whirl", "forward_whirl" or
/// "none" after the transient (Jarroux 2016, seed 001, Sec. 3); `whirl_frequency_ratio` is the
/// whirl frequency over the spin frequency, negative for backward whirl (rocking: the swing
/// frequency over the spin frequency; null for none).
inline void WriteTdbSummaries(JsonWriter& json, const RunSummary& summary) {
  json.Key("tdbs").BeginObject();
  for (std::size_t i = 0; i < summary.tdbs().size(); ++i) {
    const TdbSummary& tdb = summary.tdbs()[i];
    json.Key(tdb.name).BeginObject();
    json.Key("peak_normal_force_N").Number(tdb.peak_normal_force_N);
    json.Key("max_excursion_over_clearance").Number(tdb.max_excursion_over_clearance);
    json.Key("first_contact_time_s").Number(tdb.first_contact_time_s);
    json.Key("spinup_time_s").Number(tdb.spinup_time_s);
    const WhirlClassification whirl = summary.Whirl(i);
    json.Key("whirl").String(WhirlName(whirl.kind));
    json.Key("whirl_frequency_ratio");
    if (whirl.kind == WhirlKind::kNone) {
      json.Null();
    } else {
      json.Number(whirl.frequency_ratio);
    }
    json.EndObject();
  }
  json.EndObject();
}

}  // namespace ambdrop

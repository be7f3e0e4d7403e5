#pragma once
#include "io/json_writer.hpp"
#include "tools/run_summary.hpp"

namespace ambdrop {

/// Writes `"tdbs": {NAME: {peak_normal_force_N, max_excursion_over_clearance,
/// first_contact_time_s, spinup_time_s}, ...}` into an open JSON object (sim and hil summaries).
inline void WriteTdbSummaries(JsonWriter& json, const RunSummary& summary) {
  json.Key("tdbs").BeginObject();
  for (const TdbSummary& tdb : summary.tdbs()) {
    json.Key(tdb.name).BeginObject();
    json.Key("peak_normal_force_N").Number(tdb.peak_normal_force_N);
    json.Key("max_excursion_over_clearance").Number(tdb.max_excursion_over_clearance);
    json.Key("first_contact_time_s").Number(tdb.first_contact_time_s);
    json.Key("spinup_time_s").Number(tdb.spinup_time_s);
    json.EndObject();
  }
  json.EndObject();
}

}  // namespace ambdrop

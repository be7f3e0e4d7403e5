#include "tools/fit/prediction_csv.hpp"

#include <fmt/format.h>

#include <cmath>

namespace ambdrop {
namespace {

void Append(std::string* out, double v) {
  out->push_back(',');
  // Shortest round-trip text: a reader gets the very double the fit compared.
  if (std::isfinite(v)) *out += fmt::format("{}", v);
}

}  // namespace

std::string PredictionCsv(const MeasurementParams& m, const MeasuredRecord& r,
                          const SimulatedRecord& before, const SimulatedRecord& after) {
  std::string out = "time_s";
  for (const MeasurementChannel& ch : m.channels) {
    out += fmt::format(",{0}_measured,{0}_before,{0}_after", ch.column);
  }
  out += '\n';
  for (std::size_t j = 0; j < r.time_s.size(); ++j) {
    out += fmt::format("{}", r.time_s[j]);
    for (std::size_t c = 0; c < m.channels.size(); ++c) {
      Append(&out, r.values[r.Column(m.channels[c].column)][j]);
      Append(&out, c < before.values.size() ? before.values[c][j] : NAN);
      Append(&out, c < after.values.size() ? after.values[c][j] : NAN);
    }
    out += '\n';
  }
  return out;
}

}  // namespace ambdrop

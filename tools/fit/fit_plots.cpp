#include "tools/fit/fit_plots.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "io/files/json_writer.hpp"
#include "tools/fit/svg_plot.hpp"

namespace ambdrop {
namespace {

constexpr const char* kMeasured = "#222222";
constexpr const char* kBefore = "#d62728";
constexpr const char* kAfter = "#1f77b4";

const char* UnitOf(MeasuredQuantity q) {
  switch (q) {
    case MeasuredQuantity::kDisplacement:
      return "m";
    case MeasuredQuantity::kCurrent:
    case MeasuredQuantity::kControllerCommand:
      return "A";
    case MeasuredQuantity::kTdbNormalForce:
    case MeasuredQuantity::kTdbSupportForce:
      return "N";
    case MeasuredQuantity::kTdbSpeed:
    case MeasuredQuantity::kRotorSpeed:
      return "rad/s";
  }
  return "";
}

// The simulated rows only: what was compared.
std::vector<double> Window(const std::vector<double>& v, const SimulatedRecord& s) {
  std::vector<double> out(v.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t j = s.first_row; j < s.first_row + s.rows && j < v.size(); ++j) out[j] = v[j];
  return out;
}

}  // namespace

std::vector<std::string> WriteFitPlots(const std::filesystem::path& dir, const ModelParams& params,
                                       const MeasurementParams& m, const MeasuredRecord& r,
                                       const SimulatedRecord& before,
                                       const SimulatedRecord& after) {
  std::vector<std::string> files;
  const auto write = [&](const std::string& name, const Plot& plot) {
    WriteTextFile(dir / name, PlotSvg(plot));
    files.push_back(name);
  };
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    const MeasurementChannel& ch = m.channels[c];
    const std::vector<double> measured = Window(r.values[r.Column(ch.column)], before);
    const std::string what = ch.Describe(params);
    Plot values{what + ": measured and model",
                "time (s)",
                fmt::format("{} ({})", ch.column, UnitOf(ch.quantity)),
                {{"measured", kMeasured, r.time_s, measured},
                 {"model before", kBefore, r.time_s, before.values[c]},
                 {"model after", kAfter, r.time_s, after.values[c]}}};
    write("channel_" + ch.column + ".svg", values);
    std::vector<double> e_before(measured.size()), e_after(measured.size());
    for (std::size_t j = 0; j < measured.size(); ++j) {
      e_before[j] = measured[j] - before.values[c][j];
      e_after[j] = measured[j] - after.values[c][j];
    }
    Plot residual{what + ": residual (measured - model)",
                  "time (s)",
                  fmt::format("residual ({})", UnitOf(ch.quantity)),
                  {{"before", kBefore, r.time_s, e_before}, {"after", kAfter, r.time_s, e_after}}};
    write("residual_" + ch.column + ".svg", residual);
  }
  // Orbits where a sensor plane has both axes.
  for (std::size_t s = 0; s < params.sensors.size(); ++s) {
    int cx = -1, cy = -1;
    for (std::size_t c = 0; c < m.channels.size(); ++c) {
      const MeasurementChannel& ch = m.channels[c];
      if (ch.quantity != MeasuredQuantity::kDisplacement || ch.index != static_cast<int>(s))
        continue;
      (ch.axis == 0 ? cx : cy) = static_cast<int>(c);
    }
    if (cx < 0 || cy < 0) continue;
    const auto& x = m.channels[cx];
    const auto& y = m.channels[cy];
    Plot orbit{"orbit at sensor " + params.sensors[s].name,
               "x (m)",
               "y (m)",
               {{"measured", kMeasured, Window(r.values[r.Column(x.column)], before),
                 Window(r.values[r.Column(y.column)], before)},
                {"model before", kBefore, before.values[cx], before.values[cy]},
                {"model after", kAfter, after.values[cx], after.values[cy]}},
               true};
    write("orbit_" + params.sensors[s].name + ".svg", orbit);
  }
  return files;
}

}  // namespace ambdrop

#include "io/files/timeseries_csv.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <utility>

namespace ambdrop {
namespace {

// Rows are formatted into a string and handed to the stream in large blocks: one write per
// ~1 MiB instead of one per number keeps the output from dominating short runs.
constexpr std::size_t kFlushThresholdBytes = 1 << 20;

std::vector<std::string> SensorNames(const Model& model) {
  std::vector<std::string> names;
  for (const SensorParams& sensor : model.params.sensors) names.push_back(sensor.name);
  return names;
}

std::vector<std::string> TdbNames(const Model& model) {
  std::vector<std::string> names;
  for (const TdbParams& tdb : model.params.tdbs) names.push_back(tdb.name);
  return names;
}

std::vector<std::string> AmbNames(const Model& model) {
  std::vector<std::string> names;
  for (const AmbParams& amb : model.params.ambs) names.push_back(amb.name);
  return names;
}

void AppendNumber(std::string* line, double value) {
  line->push_back(',');
  fmt::format_to(std::back_inserter(*line), "{:.17g}", value);
}

}  // namespace

TimeseriesCsvWriter::TimeseriesCsvWriter(const std::filesystem::path& path,
                                         std::vector<std::string> sensor_names,
                                         std::vector<std::string> tdb_names,
                                         std::vector<std::string> amb_names)
    : path_(path),
      sensor_names_(std::move(sensor_names)),
      tdb_names_(std::move(tdb_names)),
      amb_names_(std::move(amb_names)) {
  if (sensor_names_.size() > static_cast<std::size_t>(kMaxSensors) ||
      tdb_names_.size() > static_cast<std::size_t>(kMaxTdbs) ||
      amb_names_.size() > static_cast<std::size_t>(kMaxAmbs)) {
    throw std::invalid_argument(fmt::format(
        "timeseries: {} sensors, {} TDBs and {} AMBs, an observation holds at most {}, {} and {}",
        sensor_names_.size(), tdb_names_.size(), amb_names_.size(), kMaxSensors, kMaxTdbs,
        kMaxAmbs));
  }
  out_.open(path_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    throw std::runtime_error(
        fmt::format("cannot open '{}' for writing: {}", path_.string(), std::strerror(errno)));
  }
  const std::vector<std::string> columns = ColumnNames(sensor_names_, tdb_names_, amb_names_);
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) buffer_.push_back(',');
    buffer_.append(columns[i]);
  }
  buffer_.push_back('\n');
}

TimeseriesCsvWriter::TimeseriesCsvWriter(const std::filesystem::path& path, const Model& model)
    : TimeseriesCsvWriter(path, SensorNames(model), TdbNames(model)) {}

TimeseriesCsvWriter::TimeseriesCsvWriter(const std::filesystem::path& path, const Model& model,
                                         bool amb_currents)
    : TimeseriesCsvWriter(path, SensorNames(model), TdbNames(model),
                          amb_currents ? AmbNames(model) : std::vector<std::string>{}) {}

TimeseriesCsvWriter::~TimeseriesCsvWriter() {
  // A destructor must not throw; callers that care about I/O errors call Close() themselves.
  try {
    Close();
  } catch (...) {
  }
}

std::vector<std::string> TimeseriesCsvWriter::ColumnNames(
    const std::vector<std::string>& sensor_names, const std::vector<std::string>& tdb_names,
    const std::vector<std::string>& amb_names) {
  std::vector<std::string> columns{"time_s"};
  for (const std::string& name : sensor_names) {
    columns.push_back(fmt::format("sensor_{}_x_m", name));
    columns.push_back(fmt::format("sensor_{}_y_m", name));
  }
  columns.push_back("spin_speed_rad_s");
  for (const std::string& name : tdb_names) {
    columns.push_back(fmt::format("tdb_{}_normal_force_N", name));
    columns.push_back(fmt::format("tdb_{}_tangential_force_N", name));
    columns.push_back(fmt::format("tdb_{}_penetration_m", name));
    columns.push_back(fmt::format("tdb_{}_spin_speed_rad_s", name));
    columns.push_back(fmt::format("tdb_{}_journal_x_m", name));
    columns.push_back(fmt::format("tdb_{}_journal_y_m", name));
  }
  for (const std::string& name : amb_names) {
    columns.push_back(fmt::format("amb_{}_x_command_A", name));
    columns.push_back(fmt::format("amb_{}_y_command_A", name));
    columns.push_back(fmt::format("amb_{}_x_coil_A", name));
    columns.push_back(fmt::format("amb_{}_y_coil_A", name));
  }
  return columns;
}

void TimeseriesCsvWriter::Write(const Observation& observation) {
  if (!amb_names_.empty()) {
    throw std::logic_error("timeseries: a writer with AMB columns needs the row's currents");
  }
  Write(observation, AmbCurrents{});
}

void TimeseriesCsvWriter::Write(const Observation& observation, const AmbCurrents& currents) {
  fmt::format_to(std::back_inserter(buffer_), "{:.17g}", observation.time_s);
  for (std::size_t i = 0; i < sensor_names_.size(); ++i) {
    AppendNumber(&buffer_, observation.sensor_xy_m[i][0]);
    AppendNumber(&buffer_, observation.sensor_xy_m[i][1]);
  }
  AppendNumber(&buffer_, observation.spin_speed_rad_s);
  for (std::size_t i = 0; i < tdb_names_.size(); ++i) {
    const TdbForce& tdb = observation.tdb[i];
    AppendNumber(&buffer_, tdb.normal_force_N);
    AppendNumber(&buffer_, tdb.tangential_force_N);
    AppendNumber(&buffer_, tdb.penetration_m);
    AppendNumber(&buffer_, tdb.tdb_spin_rad_s);
    AppendNumber(&buffer_, observation.tdb_journal_xy_m[i][0]);
    AppendNumber(&buffer_, observation.tdb_journal_xy_m[i][1]);
  }
  for (std::size_t i = 0; i < amb_names_.size(); ++i) {
    AppendNumber(&buffer_, currents.command_A[i][0]);
    AppendNumber(&buffer_, currents.command_A[i][1]);
    AppendNumber(&buffer_, currents.coil_A[i][0]);
    AppendNumber(&buffer_, currents.coil_A[i][1]);
  }
  buffer_.push_back('\n');
  ++rows_;
  if (buffer_.size() >= kFlushThresholdBytes) Flush();
}

void TimeseriesCsvWriter::Flush() {
  if (!out_.is_open()) return;
  out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  buffer_.clear();
  out_.flush();
  if (!out_) throw std::runtime_error(fmt::format("cannot write '{}'", path_.string()));
}

void TimeseriesCsvWriter::Close() {
  if (!out_.is_open()) return;
  Flush();
  out_.close();
  if (!out_) throw std::runtime_error(fmt::format("cannot write '{}'", path_.string()));
}

}  // namespace ambdrop

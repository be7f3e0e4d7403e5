#include "record_files.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace ambdrop_truth {

namespace {

std::string Quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::ofstream Open(const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error(file.string() + ": cannot write");
  return out;
}

}  // namespace

void WriteRecordCsv(const std::filesystem::path& file, const Rig& rig, const RunResult& run,
                    CsvUnits units) {
  const bool si = units == CsvUnits::kSi;
  const double length = si ? 1.0 : 1e6;  // m or um
  const double speed = si ? 1.0 : kRpmPerRadPerS;
  const char* length_unit = si ? "" : "_um";
  const char* speed_unit = si ? "" : "_rpm";
  const char* ampere = si ? "" : "_A";
  const char* newton = si ? "" : "_N";
  std::vector<std::string> header{si ? "t" : "time_ms"};
  for (const SensorRig& s : rig.sensors) {
    header.push_back(fmt::format("x_{}{}", s.name, length_unit));
    header.push_back(fmt::format("y_{}{}", s.name, length_unit));
  }
  for (const char* what : {"i", "cmd"}) {
    for (const AmbRig& a : rig.ambs) {
      header.push_back(fmt::format("{}_{}_x{}", what, a.name, ampere));
      header.push_back(fmt::format("{}_{}_y{}", what, a.name, ampere));
    }
  }
  for (const TdbRig& t : rig.tdbs) header.push_back(fmt::format("race_{}{}", t.name, speed_unit));
  header.push_back(fmt::format("rotor{}", speed_unit));
  for (const TdbRig& t : rig.tdbs) header.push_back(fmt::format("fn_{}{}", t.name, newton));
  for (const TdbRig& t : rig.tdbs) {
    header.push_back(fmt::format("Fx_{}{}", t.name, newton));
    header.push_back(fmt::format("Fy_{}{}", t.name, newton));
  }

  std::string text;
  for (std::size_t i = 0; i < header.size(); ++i) text += (i ? "," : "") + header[i];
  text += '\n';
  for (const RecordRow& r : run.rows) {
    // 17 significant digits in SI (the values parse back to the same bits); the acquisition's
    // own file carries what its ADCs resolve.
    const auto put = [&](double v) {
      text += si ? fmt::format(",{:.17g}", v) : fmt::format(",{:.6f}", v);
    };
    text += si ? fmt::format("{:.17g}", r.t_s) : fmt::format("{:.4f}", r.t_s * 1e3);
    for (int s = 0; s < 2; ++s) {
      for (int axis = 0; axis < 2; ++axis) put(r.displacement_m[s][axis] * length);
    }
    for (const auto* block : {&r.current_A, &r.command_A}) {
      for (int a = 0; a < 2; ++a) {
        for (int axis = 0; axis < 2; ++axis) put((*block)[a][axis]);
      }
    }
    for (int t = 0; t < 2; ++t) put(r.race_speed_rad_s[t] * speed);
    put(r.rotor_speed_rad_s * speed);
    for (int t = 0; t < 2; ++t) put(r.normal_force_N[t]);
    for (int t = 0; t < 2; ++t) {
      put(r.support_force_N[t][0]);
      put(r.support_force_N[t][1]);
    }
    text += '\n';
  }
  std::ofstream out = Open(file);
  out << text;
}

void WriteTruthJson(const std::filesystem::path& file, const Truth& truth, std::uint64_t seed,
                    const std::string& rig_file, double generation_s) {
  std::string text = "{\n";
  text += fmt::format("  \"effect\": {},\n", Quoted(truth.effect));
  if (!truth.entry.empty()) text += fmt::format("  \"entry\": {},\n", Quoted(truth.entry));
  text += fmt::format("  \"description\": {},\n", Quoted(truth.description));
  text += fmt::format("  \"seed\": {},\n", seed);
  text += fmt::format("  \"rig\": {},\n", Quoted(rig_file));
  text += fmt::format("  \"ambdrop_mapping\": {},\n", Quoted(truth.mapping));
  text += fmt::format("  \"ambdrop_mapping_note\": {},\n", Quoted(truth.mapping_note));
  text += "  \"generator_parameters\": {";
  for (std::size_t i = 0; i < truth.generator_parameters.size(); ++i) {
    text += fmt::format("{}\n    {}: {:.17g}", i ? "," : "",
                        Quoted(truth.generator_parameters[i].first),
                        truth.generator_parameters[i].second);
  }
  text += truth.generator_parameters.empty() ? "},\n" : "\n  },\n";
  text += "  \"ambdrop_set\": [";
  for (std::size_t i = 0; i < truth.ambdrop_keys.size(); ++i) {
    text += fmt::format("{}\n    {}", i ? "," : "",
                        Quoted(truth.ambdrop_keys[i].first + "=" + truth.ambdrop_keys[i].second));
  }
  text += truth.ambdrop_keys.empty() ? "],\n" : "\n  ],\n";
  text += fmt::format("  \"generation_s\": {:.3f}\n}}\n", generation_s);
  std::ofstream out = Open(file);
  out << text;
}

}  // namespace ambdrop_truth

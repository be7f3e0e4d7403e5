#pragma once
// What one record leaves on disk, as a user would have it from the acquisition:
//   record.csv      time in ms, displacements in um, currents in A, speeds in rpm, forces in N
//   record_si.csv   (with --si) the same in SI with a `t` column, as ambdrop fit reads today
//   declared.json   the rig sheet (the rig file, without the hidden effect)
//   truth.json      the hidden effect: the generator's parameters and ambdrop's keys
#include <filesystem>
#include <string>

#include "drop_run.hpp"
#include "effects.hpp"
#include "rig.hpp"

namespace ambdrop_truth {

enum class CsvUnits { kAcquisition, kSi };

void WriteRecordCsv(const std::filesystem::path& file, const Rig& rig, const RunResult& run,
                    CsvUnits units);

void WriteTruthJson(const std::filesystem::path& file, const Truth& truth, std::uint64_t seed,
                    const std::string& rig_file, double generation_s);

}  // namespace ambdrop_truth

// ambdrop_truth: an independent truth generator for `ambdrop fit` (issue 15, item 2). It shares
// no code with ambdrop's physics, I/O or controller; see tools/truth/README.md.
//
//   ambdrop_truth --rig R.json --effect NAME --seed N --out DIR [--si]
//   ambdrop_truth --rig R.json --battery DIR [--si]
//   ambdrop_truth --rig R.json --battery-declared DIR [--count N] [--si]
//   ambdrop_truth [--rig R.json] --list
#include <fmt/format.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "declared_off.hpp"
#include "drop_run.hpp"
#include "effects.hpp"
#include "noise.hpp"
#include "record_files.hpp"
#include "rig.hpp"

namespace fs = std::filesystem;
using namespace ambdrop_truth;

namespace {

constexpr int kBadCommandLine = 64;

struct Args {
  std::string rig;
  std::string effect;
  std::uint64_t seed = 1;
  std::uint64_t first_seed = 0;  ///< --battery's first seed (0: the default, 1 or 101)
  std::string out;
  std::string battery;
  std::string battery_declared;
  int count = 12;
  bool si = false;
  bool list = false;
  bool noise = true;
  bool exact_record = false;
};

void Usage() {
  std::fputs(
      "usage: ambdrop_truth --rig R.json --effect NAME --seed N --out DIR [--si] [--no-noise]\n"
      "                     [--exact-record]\n"
      "       ambdrop_truth --rig R.json --battery DIR [--first-seed S] [--si]\n"
      "       ambdrop_truth --rig R.json --battery-declared DIR [--count N] [--first-seed S] "
      "[--si]\n"
      "       ambdrop_truth [--rig R.json] --list\n"
      "NAME: a kind of --list; declared_off (one number of the rig sheet off, drawn by the\n"
      "seed) or declared_off:ENTRY (that number; --rig R.json --list names the entries)\n"
      "--exact-record: the record's channels without acquisition noise or quantisation, the\n"
      "controller's sensors still noisy (the same motion, seen exactly: a diagnosis)\n",
      stderr);
}

/// A record the generator refuses: its run left the physics it models.
struct OutsidePhysics : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Makes one record in `dir`, and its blind copy in `blind_dir`; returns the seconds taken.
double MakeRecord(const Args& args, const std::string& effect, std::uint64_t seed,
                  const fs::path& dir, const fs::path& blind_dir) {
  const auto start = std::chrono::steady_clock::now();
  const Rig declared = ReadRig(args.rig);
  Rig actual = declared;
  const Truth truth = ApplyEffect(effect, seed, &actual);
  CheckRig(actual);
  RunOptions options;
  options.add_noise = args.noise;
  options.exact_record = args.exact_record;
  if (!args.noise) actual.acquisition.sensor_quantisation_m = 0.0;
  const RunResult run = RunDrop(actual, seed, options);
  if (!run.finite) throw std::runtime_error(effect + ": the run diverged");
  if (!run.left_physics.empty()) throw OutsidePhysics(effect + ": " + run.left_physics);
  fs::create_directories(dir);
  fs::create_directories(blind_dir);
  for (const fs::path& d : {dir, blind_dir}) {
    WriteRecordCsv(d / "record.csv", declared, run, CsvUnits::kAcquisition);
    if (args.si) WriteRecordCsv(d / "record_si.csv", declared, run, CsvUnits::kSi);
    fs::copy_file(args.rig, d / "declared.json", fs::copy_options::overwrite_existing);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WriteTruthJson(dir / "truth.json", truth, seed, args.rig, seconds);
  fmt::print("{:<24} seed {:<4} {:6.2f} s  {}\n", effect, seed, seconds, truth.description);
  return seconds;
}

}  // namespace

int main(int argc, char** argv) {
  Args args;
  const std::vector<std::string> a(argv + 1, argv + argc);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto value = [&]() -> std::string {
      if (i + 1 >= a.size()) {
        fmt::print(stderr, "{} needs a value\n", a[i]);
        std::exit(kBadCommandLine);
      }
      return a[++i];
    };
    if (a[i] == "--rig") {
      args.rig = value();
    } else if (a[i] == "--effect") {
      args.effect = value();
    } else if (a[i] == "--seed") {
      const std::string v = value();
      try {
        args.seed = std::stoull(v);
      } catch (const std::exception&) {
        fmt::print(stderr, "--seed: expected a non-negative integer, found '{}'\n", v);
        return kBadCommandLine;
      }
    } else if (a[i] == "--first-seed") {
      const std::string v = value();
      try {
        std::size_t used = 0;
        args.first_seed = std::stoull(v, &used);
        if (used != v.size() || args.first_seed == 0 || v[0] == '-') throw std::invalid_argument(v);
      } catch (const std::exception&) {
        fmt::print(stderr, "--first-seed: expected a positive integer, found '{}'\n", v);
        return kBadCommandLine;
      }
    } else if (a[i] == "--out") {
      args.out = value();
    } else if (a[i] == "--battery") {
      args.battery = value();
    } else if (a[i] == "--battery-declared") {
      args.battery_declared = value();
    } else if (a[i] == "--count") {
      const std::string v = value();
      try {
        std::size_t used = 0;
        args.count = std::stoi(v, &used);
        if (used != v.size() || args.count < 0) throw std::invalid_argument(v);
      } catch (const std::exception&) {
        fmt::print(stderr, "--count: expected a non-negative integer, found '{}'\n", v);
        return kBadCommandLine;
      }
    } else if (a[i] == "--si") {
      args.si = true;
    } else if (a[i] == "--no-noise") {
      args.noise = false;
    } else if (a[i] == "--exact-record") {
      args.exact_record = true;
    } else if (a[i] == "--list") {
      args.list = true;
    } else if (a[i] == "--help" || a[i] == "-h") {
      Usage();
      return 0;
    } else {
      fmt::print(stderr, "unknown argument '{}'\n", a[i]);
      Usage();
      return kBadCommandLine;
    }
  }
  if (args.list) {
    for (const std::string& k : EffectKinds()) fmt::print("{}\n", k);
    fmt::print("declared_off\n");
    if (args.rig.empty()) {
      fmt::print(stderr, "(with --rig R.json: the rig's declared_off:ENTRY names too)\n");
      return 0;
    }
    try {
      for (const DeclaredEntry& e : DeclaredOffEntries(ReadRig(args.rig))) {
        fmt::print("declared_off:{}\n", e.name);
      }
    } catch (const std::exception& e) {
      fmt::print(stderr, "ambdrop_truth: {}\n", e.what());
      return 1;
    }
    return 0;
  }
  const int modes = !args.battery.empty() + !args.battery_declared.empty() +
                    (!args.effect.empty() || !args.out.empty());
  if (args.rig.empty() || modes != 1 ||
      (args.battery.empty() && args.battery_declared.empty() &&
       (args.effect.empty() || args.out.empty() || args.first_seed > 0))) {
    Usage();
    return kBadCommandLine;
  }
  try {
    if (args.battery.empty() && args.battery_declared.empty()) {
      const fs::path dir(args.out);
      MakeRecord(args, args.effect, args.seed, dir, dir / "blind");
      return 0;
    }
    // --battery: every kind once, the clean record twice (seeds 1..17). --battery-declared
    // (issue 23): the clean record twice (seeds 1, 2), then --count declared_off records
    // (seeds 101, 102, ...). --first-seed S moves the first seed (of the declared_off draws):
    // the same kinds, other sizes and jitters, records no rule was made on. Blind copies under
    // names that do not give the effect away, and battery.json to map them back.
    const bool declared = !args.battery_declared.empty();
    const fs::path root(declared ? args.battery_declared : args.battery);
    std::vector<std::pair<std::string, std::uint64_t>> plan;
    if (declared) {
      plan.emplace_back("clean", 1);
      plan.emplace_back("clean", 2);
      const std::uint64_t first = args.first_seed > 0 ? args.first_seed : 101;
      for (int i = 0; i < args.count; ++i) {
        plan.emplace_back("declared_off", first + static_cast<std::uint64_t>(i));
      }
    } else {
      std::uint64_t seed = args.first_seed > 0 ? args.first_seed : 1;
      for (const std::string& kind : EffectKinds()) {
        plan.emplace_back(kind, seed++);
        if (kind == "clean") plan.emplace_back(kind, seed++);
      }
    }
    std::string index = "[\n";
    double total_s = 0.0;
    for (std::size_t i = 0; i < plan.size(); ++i) {
      std::uint64_t h = plan[i].second * 0x9e3779b97f4a7c15ULL + i;
      const std::string blind = fmt::format("record_{:06x}", SplitMix64(&h) & 0xffffff);
      const std::string name = fmt::format("{:02}_{}_s{}", i, plan[i].first, plan[i].second);
      // A draw whose drop leaves the modelled physics is listed, not made: the battery
      // reports it and scores the others.
      std::string not_made;
      try {
        total_s +=
            MakeRecord(args, plan[i].first, plan[i].second, root / name, root / "blind" / blind);
      } catch (const OutsidePhysics& e) {
        for (const char c : std::string(e.what())) {
          if (c == '"' || c == '\\') not_made += '\\';
          not_made += c;
        }
        fmt::print("{:<24} seed {:<4} not made: {}\n", plan[i].first, plan[i].second, not_made);
      }
      const std::string tail = i + 1 < plan.size() ? "," : "";
      index += not_made.empty()
                   ? fmt::format("  {{\"record\": \"{}\", \"blind\": \"blind/{}\"}}{}\n", name,
                                 blind, tail)
                   : fmt::format("  {{\"record\": \"{}\", \"not_made\": \"{}\"}}{}\n", name,
                                 not_made, tail);
    }
    index += "]\n";
    std::FILE* f = std::fopen((root / "battery.json").c_str(), "w");
    if (f == nullptr) throw std::runtime_error((root / "battery.json").string() + ": cannot write");
    std::fputs(index.c_str(), f);
    std::fclose(f);
    fmt::print("{} records in {:.1f} s ({:.2f} s each)\n", plan.size(), total_s,
               total_s / static_cast<double>(plan.size()));
  } catch (const std::exception& e) {
    fmt::print(stderr, "ambdrop_truth: {}\n", e.what());
    return 1;
  }
  return 0;
}

#include "tools/fit/fit_report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "io/files/json_writer.hpp"
#include "tools/fit/fit_plots.hpp"
#include "tools/fit/prediction_csv.hpp"

namespace ambdrop {
namespace {

void Residuals(JsonWriter& json, const ResidualReport& r, double noise_floor) {
  json.BeginObject();
  json.Key("overall").Number(r.overall);
  json.Key("overall_above_noise").Number(AboveNoise(r.overall, noise_floor));
  json.Key("channels").BeginObject();
  for (const ChannelResidual& c : r.channels) {
    json.Key(c.column).BeginObject();
    json.Key("quantity").String(c.description);
    json.Key("rms").Number(c.rms);
    json.Key("relative").Number(c.rms / c.scale);
    json.Key("before_trigger").Number(c.rms_before);
    json.Key("impact").Number(c.rms_impact);
    json.Key("settled").Number(c.rms_settled);
    json.Key("samples").Integer(static_cast<std::int64_t>(c.samples));
    if (std::isfinite(c.cost_share)) json.Key("cost_share").Number(c.cost_share);
    json.EndObject();
  }
  json.EndObject();
  json.Key("features").BeginArray();
  for (const FeatureComparison& f : r.features) {
    json.BeginObject(true);
    json.Key("feature").String(f.feature);
    json.Key("channel").String(f.channel);
    json.Key("measured").Number(f.measured);
    json.Key("model").Number(f.model);
    json.EndObject();
  }
  json.EndArray();
  json.EndObject();
}

bool Suggested(const ResidualReport& before, const std::string& family) {
  for (const Signature& s : before.signatures) {
    for (const std::string& f : s.points_to) {
      if (family.find(f) != std::string::npos) return true;
    }
  }
  return false;
}

const Effect* Find(const std::vector<Effect>& library, const std::string& name) {
  for (const Effect& e : library) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

void Parameters(JsonWriter& json, const EffectFit& fit, const std::string& effect) {
  json.BeginObject();
  for (const ParameterEstimate& p : fit.parameters) {
    if (p.effect != effect) continue;
    json.Key(p.name).BeginObject(true);
    json.Key("value").Number(p.value);
    json.Key("sigma").Number(p.sigma);
    if (std::isfinite(p.start_sigma)) json.Key("start_sigma").Number(p.start_sigma);
    json.Key("decided").Bool(p.decided);
    if (std::isfinite(p.declared_rms)) json.Key("declared_rms").Number(p.declared_rms);
    if (std::isfinite(p.explained_at)) json.Key("explained_at").Number(p.explained_at);
    if (!p.traded_with.empty()) {
      // The record decides traded_with - slope * this (declared_value_check.hpp).
      json.Key("trades_with").BeginObject(true);
      json.Key("parameter").String(p.traded_with);
      json.Key("slope").Number(p.trade_slope);
      json.Key("combination").Number(p.trade_combination);
      json.Key("combination_sigma").Number(p.trade_combination_sigma);
      json.EndObject();
    }
    json.EndObject();
  }
  json.EndObject();
}

// Which mode drove the AMBs after the trigger, and what it leaves undecidable.
std::string FromRecordNote(const ModelParams& params, const MeasurementParams& m) {
  if (m.power_loss != PowerLossSource::kFromRecord) return {};
  std::string columns;
  std::vector<std::string> magnets;
  for (const MeasurementChannel& ch : m.channels) {
    if (!m.Drives(ch)) continue;
    columns += (columns.empty() ? "" : ", ") + ch.column;
    const AmbParams& a = params.ambs[static_cast<std::size_t>(ch.index)];
    if (a.bias_source == AmbBiasSource::kPermanentMagnet &&
        std::find(magnets.begin(), magnets.end(), a.name) == magnets.end()) {
      magnets.push_back(a.name);
    }
  }
  std::string md = fmt::format(
      "Power loss: **from_record**. The record's coil currents ({}) drove their AMB axes through "
      "and after the trigger and are not compared; ",
      columns);
  md += magnets.empty()
            ? "the electromagnet bias under them fell by the declared law, so its keys stay "
              "candidates.\n\n"
            : fmt::format(
                  "the power-loss keys of magnet-biased AMB(s) {} cannot be decided from "
                  "this record (their force follows the recorded current).\n\n",
                  fmt::join(magnets, ", "));
  return md;
}

}  // namespace

void DiscrepancyJson(JsonWriter& json, const Discrepancy& d) {
  json.BeginObject();
  json.Key("dominant").Bool(d.dominant);
  json.Key("channel").String(d.channel);
  json.Key("description").String(d.description);
  json.Key("share").Number(d.share);
  json.Key("phase").String(d.phase);
  json.Key("shape").String(d.shape);
  json.Key("record_value").Number(d.record_value);
  json.Key("model_value").Number(d.model_value);
  json.Key("key_families").BeginArray(true);
  for (const std::string& f : d.key_families) json.String(f);
  json.EndArray();
  json.EndObject();
}

std::string FitJson(const FitOutcome& o, const ModelParams&, const MeasurementParams& m) {
  const Selection& s = *o.selection;
  JsonWriter json;
  json.BeginObject();
  // 2: a chosen effect's "set" (its --set lines) replaced its TOML text "config", and
  // "equivalent" lists objects (effect, family, rms_after, parameters, set), not names.
  json.Key("schema_version").Integer(2);
  json.Key("config").String(o.config_path);
  json.Key("measured").String(o.measured_path);
  json.Key("verdict").String(s.verdict);
  json.Key("reason").String(s.reason);
  if (o.discrepancy != nullptr) {
    json.Key("discrepancy");
    DiscrepancyJson(json, *o.discrepancy);
  }
  json.Key("power_loss")
      .String(m.power_loss == PowerLossSource::kFromRecord ? "from_record" : "declared");
  json.Key("driving_channels").BeginArray();
  for (const MeasurementChannel& ch : m.channels) {
    if (m.Drives(ch)) json.String(ch.column);
  }
  json.EndArray();
  if (m.trigger_state_from_record || m.trigger_state_for_start) {
    json.Key("trigger_state").String(m.trigger_state_for_start ? "record_start" : "record");
    json.Key("trigger_state_fit").String(s.trigger_state);
  }
  if (s.jitter.ran) {
    json.Key("jitter_draws").BeginObject();
    json.Key("drawn").String(s.jitter.from_estimate ? "trigger_state_estimate"
                                                    : "controller_noise");
    json.Key("jitter_sigma_m").Number(s.jitter.jitter_sigma_m);
    json.Key("runs").Integer(s.jitter.draws);
    json.Key("first_within_limit").Integer(s.jitter.first_within);
    if (std::isfinite(s.jitter.closest_rms)) {
      json.Key("closest_rms").Number(s.jitter.closest_rms);
    }
    json.Key("extended").Bool(s.jitter.extended);
    json.Key("record_mode").String(s.jitter.record_mode);
    json.Key("declared_mode").String(s.jitter.model_mode);
    json.Key("first_in_record_mode").Integer(s.jitter.first_match);
    json.EndObject();
  }
  if (o.sensor_noise != nullptr) {
    json.Key("sensor_noise").BeginObject();
    json.Key("sigma_m").Number(o.sensor_noise->sigma_m);
    json.Key("bandwidth_Hz").Number(o.sensor_noise->bandwidth_Hz);
    json.Key("second_difference_sigma_m").Number(o.sensor_noise->white_sigma_m);
    json.EndObject();
  }
  json.Key("noise_floor").Number(s.noise_floor);
  json.Key("model_floor").Number(s.model_floor);
  json.Key("step_sensitivity").Number(s.step_sensitivity);
  json.Key("start_sensitivity").Number(s.start_sensitivity);
  json.Key("model_floor_after").Number(s.model_floor_after);
  json.Key("agreement_limit").Number(s.limit);
  json.Key("agreement_limit_after").Number(s.limit_after);
  json.Key("agreement_limit_after_capped").Bool(s.limit_after_capped);
  if (o.step != nullptr) {
    json.Key("step").BeginObject(true);
    json.Key("declared_s").Number(o.step->declared_s);
    json.Key("fit_s").Number(o.step->step_s);
    json.Key("move_over_noise").Number(o.step->move_over_noise);
    json.Key("limit_widening").Number(o.step->limit_widening);
    json.Key("why").String(o.step->why);
    json.EndObject();
  }
  json.Key("windows").BeginObject(true);
  json.Key("start_s").Number(o.before.windows.start_s);
  json.Key("trigger_s").Number(o.before.windows.trigger_s);
  json.Key("trigger_detected").Bool(m.detect_trigger);
  json.Key("impact_end_s").Number(o.before.windows.impact_end_s);
  json.Key("settled_start_s").Number(o.before.windows.settled_start_s);
  json.Key("end_s").Number(o.before.windows.end_s);
  json.EndObject();
  json.Key("rms_before");
  Residuals(json, o.before, s.whole.noise_floor);
  json.Key("rms_after");
  Residuals(json, o.after, s.whole.noise_floor);

  json.Key("signatures").BeginArray();
  for (const Signature& sig : o.before.signatures) {
    json.BeginObject(true);
    json.Key("kind").String(sig.kind);
    json.Key("channel").String(sig.channel);
    json.Key("value").Number(sig.value);
    json.Key("relative").Number(sig.relative);
    json.Key("points_to").BeginArray(true);
    for (const std::string& f : sig.points_to) json.String(f);
    json.EndArray();
    json.EndObject();
  }
  json.EndArray();

  json.Key("chosen").BeginArray();
  for (std::size_t e = 0; e < o.chosen.size(); ++e) {
    json.BeginObject();
    json.Key("effect").String(o.chosen[e]->name);
    json.Key("description").String(o.chosen[e]->description);
    json.Key("parameters");
    Parameters(json, s.chosen_fit, o.chosen[e]->name);
    // What `--set` takes, as it was applied: each line one override of the declared config.
    json.Key("set").BeginArray();
    for (const std::string& line : o.chosen[e]->overrides(s.chosen_fit.values[e])) {
      json.String(line);
    }
    json.EndArray();
    json.EndObject();
  }
  json.EndArray();

  // Each look-alike with its own fit, side by side with the chosen one.
  json.Key("equivalent").BeginArray();
  for (const EquivalentEffect& e : s.equivalent) {
    json.BeginObject();
    json.Key("effect").String(e.name);
    json.Key("family").String(e.family);
    json.Key("rms_after").Number(e.rms_after);
    json.Key("separating_channel").String(e.separating_channel);
    json.Key("separation_over_noise").Number(e.separation_over_noise);
    json.Key("parameters");
    Parameters(json, e.fit, e.name);
    json.Key("set").BeginArray();
    if (const Effect* effect = Find(*o.library, e.name); effect && !e.fit.values.empty()) {
      for (const std::string& line : effect->overrides(e.fit.values.front())) json.String(line);
    }
    json.EndArray();
    json.EndObject();
  }
  json.EndArray();

  // The parts the verdict looks at; the top-level numbers are the judged one's.
  json.Key("judged_on").String(s.judged_on);
  for (const auto& [name, part] :
       {std::pair{"whole", &s.whole}, std::pair{"early", &s.early},
        std::pair{"sensors", &s.sensors}, std::pair{"speeds", &s.speeds},
        std::pair{"levitated", &s.levitated}, std::pair{"spectrum", &s.spectrum}}) {
    if (!part->compared) continue;
    json.Key(name).BeginObject();
    json.Key("rms_before").Number(part->rms_before);
    json.Key("rms_after").Number(part->rms_after);
    json.Key("noise_floor").Number(part->noise_floor);
    json.Key("step_sensitivity").Number(part->step_sensitivity);
    json.Key("start_sensitivity").Number(part->start_sensitivity);
    json.Key("agreement_limit").Number(part->limit);
    json.Key("agreement_limit_after")
        .Number(part->limit_after > 0 ? part->limit_after : part->limit);
    if (!part->columns.empty()) {
      json.Key("columns").BeginArray();
      for (const std::string& column : part->columns) json.String(column);
      json.EndArray();
    }
    json.EndObject();
  }
  if (!s.closest.empty()) {
    // An unexplained verdict's nearest miss: not applied, named so the user sees what came close.
    json.Key("closest").BeginObject();
    json.Key("effects").BeginArray();
    for (const std::string& name : s.closest) json.String(name);
    json.EndArray();
    json.Key("rms_after").Number(s.closest_rms);
    json.EndObject();
  }
  json.Key("unconfirmed_departure").Bool(s.unconfirmed_departure);
  json.Key("start_within_state_uncertainty").Bool(s.start_within_state_uncertainty);
  if (s.start_shift.fitted) {
    // The declared model with the state at the trigger shifted within its estimate's
    // uncertainty, on the drop's start (start_state_shift.hpp).
    json.Key("start_state_shift").BeginObject();
    const StartStateShift& shift = s.start_shift;
    for (const auto& [key, value] :
         {std::pair{"sigmas", shift.sigmas}, std::pair{"plausible_sigmas", shift.plausible_sigmas},
          std::pair{"directions", shift.directions}, std::pair{"rms_before", shift.rms_before},
          std::pair{"rms_after", shift.rms_after}}) {
      json.Key(key).Number(value);
    }
    json.Key("runs").Integer(s.start_shift.runs);
    json.EndObject();
  }
  json.Key("decidable_candidates").Integer(s.decidable_candidates);
  json.Key("candidates").BeginArray();
  for (const CandidateScore& c : s.candidates) {
    json.BeginObject();
    json.Key("effect").String(c.name);
    json.Key("family").String(c.family);
    json.Key("decidable").Bool(c.decidable);
    if (!c.refused.empty()) json.Key("refused").String(c.refused);
    json.Key("suggested_by_signatures").Bool(Suggested(o.before, c.family));
    json.Key("tried").Bool(c.tried);
    json.Key("screened").Bool(c.screened);
    if (std::isfinite(c.reach)) json.Key("reach").Number(c.reach);
    if (std::isfinite(c.screened_rms)) json.Key("screened_rms").Number(c.screened_rms);
    if (c.tried) {
      json.Key("rms_after").Number(c.rms_after);
      json.Key("delta_bic").Number(c.delta_bic);
      json.Key("accepted").Bool(c.accepted);
      json.Key("runs").Integer(c.fit.evaluations);
      json.Key("parameters").BeginObject();
      for (const ParameterEstimate& p : c.fit.parameters) {
        json.Key(c.fit.effects.size() > 1 ? p.effect + "." + p.name : p.name).BeginObject(true);
        json.Key("value").Number(p.value);
        json.Key("sigma").Number(p.sigma);
        json.Key("decided").Bool(p.decided);
        json.EndObject();
      }
      json.EndObject();
    }
    json.EndObject();
  }
  json.EndArray();

  json.Key("undecidable").BeginArray();
  for (const Effect& e : *o.library) {
    const CandidateScore* c = nullptr;
    for (const CandidateScore& x : s.candidates) {
      if (x.name == e.name) c = &x;
    }
    if (c == nullptr || c->decidable) continue;
    json.BeginObject(true);
    json.Key("effect").String(e.name);
    if (!c->refused.empty()) json.Key("refused").String(c->refused);
    // The quantities that would reveal it and the record lacks.
    json.Key("needs").BeginArray(true);
    for (const MeasuredQuantity q : e.revealed_by) {
      bool measured = false;
      for (const MeasurementChannel& ch : m.channels) measured = measured || ch.quantity == q;
      if (!measured) json.String(MeasuredQuantityName(q));
    }
    json.EndArray();
    if (std::isfinite(c->reach)) {
      json.Key("reach").Number(c->reach);
      json.Key("why").String("at its probe values the prediction moves within the agreement limit");
    } else {
      json.Key("why").String("no channel of the record can reveal it");
    }
    json.EndObject();
  }
  json.EndArray();
  json.Key("wall_time_s").Number(o.wall_time_s);
  json.EndObject();
  return json.str();
}

void WriteFitReport(const std::filesystem::path& dir, const FitOutcome& o,
                    const ModelParams& params, const MeasurementParams& m,
                    const MeasuredRecord& record, const SimulatedRecord& before,
                    const SimulatedRecord& after) {
  const Selection& s = *o.selection;
  const std::vector<std::string> plots = WriteFitPlots(dir, params, m, record, before, after);
  WriteTextFile(dir / "prediction.csv", PredictionCsv(m, record, before, after));
  std::string md;
  md += fmt::format("# Fit of {} to {}\n\n", o.config_path, o.measured_path);
  md += fmt::format("**Verdict: {}.** {}.\n\n", s.verdict, s.reason);
  md += fmt::format(
      "Judged on {}: relative RMS residual {:.4g} before, {:.4g} after; the record's noise "
      "alone would leave {:.3g}, so the model error is {:.3g} before and {:.3g} after.\n\n",
      s.judged_on == "early" ? "the drop's start (every channel up to just after the first "
                               "impact), where it departs beyond its limit"
      : s.judged_on == "sensors"
          ? "the drop's start on the sensors that depart alone (each displacement channel held to "
            "a limit of its own: its noise and its widest move under the start's probes and "
            "drawn jitters), where the start as a whole agrees"
      : s.judged_on == "speeds" ? "the speeds (rotor and races, from the trigger to the end), "
                                  "which depart further beyond their limit than the whole record"
      : s.judged_on == "levitated"
          ? "the levitated time before the trigger (each displacement's and current's mean, 1X "
            "and 2X there, from the model's own levitated state), where it departs beyond its "
            "limit"
      : s.judged_on == "spectrum"
          ? "the levitated currents' noise spectrum (what the loop does with its sensors' noise, "
            "each band in units of its own spread, from noise draws of the model's controller), "
            "where it departs beyond its limit"
          : "the whole record",
      s.rms_before, s.rms_after, s.noise_floor, AboveNoise(s.rms_before, s.noise_floor),
      AboveNoise(s.rms_after, s.noise_floor));
  if (m.detect_trigger) {
    // A late trigger shifts every later sample: the verdict depends on it.
    md += fmt::format(
        "The trigger was found in the record at {:.6g} s (measurement.trigger = \"detect\", "
        "tools/fit/record_trigger_detect.hpp): where the power loss shows at once (currents cut) "
        "within half a sample, where it shows slowly (a hold before the fall, a slow decay or "
        "ramp) only once its effect leaves the noise, later by that time. Give trigger_time_s "
        "where the acquisition knows it.\n\n",
        o.before.windows.trigger_s);
  }
  if (o.sensor_noise != nullptr && o.sensor_noise->bandwidth_Hz > 0.0) {
    md += fmt::format(
        "The displacement sensors' noise is coloured (tools/fit/sensor_noise_colour.hpp): its "
        "levitated spectrum falls as a first-order low-pass at {:.4g} Hz, sigma {:.3g} m, where "
        "second differences read {:.3g} m. The model's controller answers noise of that colour "
        "wherever the rotor's jitter is drawn (sensor.NAME.noise.bandwidth_Hz), and each "
        "displacement is judged against that sigma.\n\n",
        o.sensor_noise->bandwidth_Hz, o.sensor_noise->sigma_m, o.sensor_noise->white_sigma_m);
  }
  md += FromRecordNote(params, m);
  if (m.trigger_state_from_record) {
    md += fmt::format("The state at the trigger (measurement.trigger_state = \"record\"): {}.\n\n",
                      s.trigger_state);
  } else if (m.trigger_state_for_start) {
    md += fmt::format(
        "The state at the trigger (measurement.trigger_state = \"record_start\"): for the drop's "
        "start, {}; for the rest of the record, the model's own levitated state.\n\n",
        s.trigger_state);
  }
  if (o.step != nullptr) {
    md += fmt::format("Every run of the fit took a step of {:.3g} s (declared {:.3g} s): {}.\n\n",
                      o.step->step_s, o.step->declared_s, o.step->why);
  }
  for (const auto& [name, part] :
       {std::pair{"The whole record", &s.whole}, std::pair{"The drop's start", &s.early},
        std::pair{"The drop's start on the departing sensors", &s.sensors},
        std::pair{"The speeds", &s.speeds},
        std::pair{"The levitated time (mean, 1X, 2X)", &s.levitated},
        std::pair{"The levitated currents' noise spectrum", &s.spectrum}}) {
    if (!part->compared) continue;
    md += fmt::format(
        "- {}: {:.4g} before, {:.4g} after, agreement limit {:.3g} (noise {:.3g}, step "
        "sensitivity {:.3g}, start sensitivity {:.3g}).\n",
        name, part->rms_before, part->rms_after, part->limit, part->noise_floor,
        part->step_sensitivity, part->start_sensitivity);
  }
  md += "\n";
  if (o.discrepancy != nullptr && o.discrepancy->dominant) {
    const Discrepancy& d = *o.discrepancy;
    md += "## The declared model against the rig\n\n";
    md += fmt::format(
        "No candidate removes most of the residual: the declared model does not match the rig "
        "here. {:.0f} % of what is left sits on '{}' ({}, {}): {}. Config keys that could "
        "explain it:\n\n",
        100.0 * d.share, d.channel, d.description, d.phase, d.shape);
    for (const std::string& f : d.key_families) md += "- `" + f + "`\n";
    md += "\n";
  }
  if (!o.chosen.empty()) {
    md += "## Chosen effects\n\n";
    for (std::size_t e = 0; e < o.chosen.size(); ++e) {
      md += fmt::format("- **{}**: {}\n", o.chosen[e]->name, o.chosen[e]->description);
      for (const ParameterEstimate& p : s.chosen_fit.parameters) {
        if (p.effect == o.chosen[e]->name) {
          md += fmt::format(
              "  - {} = {:.6g} ± {:.2g}{}{}\n", p.name, p.value, p.sigma,
              std::isfinite(p.start_sigma) && std::isfinite(p.sigma)
                  ? fmt::format(" (the rotor's jitter at the trigger {:.2g} of it)", p.start_sigma)
                  : "",
              p.decided ? ""
              : std::isfinite(p.explained_at)
                  ? fmt::format(
                        " (not decided: at {:.4g}, with its most correlated value following, the "
                        "record is explained as well; the model runs with it, but it measures "
                        "nothing)",
                        p.explained_at)
              : !p.traded_with.empty()
                  ? fmt::format(
                        " (not decided alone: it trades with {} along a valley of the record's "
                        "cost; what the record decides is {} {} {:.4g} x {} = {:.6g} ± {:.2g})",
                        p.traded_with, p.traded_with, p.trade_slope <= 0.0 ? "+" : "-",
                        std::abs(p.trade_slope), p.name, p.trade_combination,
                        p.trade_combination_sigma)
              : std::isfinite(p.declared_rms)
                  ? fmt::format(
                        " (not decided: at its declared value, the rest as fitted, the record is "
                        "explained as well, {:.3g} on the judged part; the model runs with it, "
                        "but it measures nothing)",
                        p.declared_rms)
                  : " (not decided: the record leaves it open; the model runs with it, "
                    "but it measures nothing)");
        }
      }
      // Exactly what was applied: the --set lines of the declared config.
      md += "\n  ```\n";
      for (const std::string& line : o.chosen[e]->overrides(s.chosen_fit.values[e])) {
        md += "  --set " + line + "\n";
      }
      md += "  ```\n";
    }
    md += "\n";
  }
  if (!s.equivalent.empty()) {
    // Side by side with the chosen one: the record does not decide between them.
    md += "## Explanations the record cannot tell apart\n\n";
    md +=
        "| effect | parameters | overall RMS after | departs most from the chosen on |\n"
        "|---|---|---|---|\n";
    const auto row = [&](const std::string& name, const EffectFit& fit, double rms,
                         const std::string& apart) {
      std::string params;
      for (const ParameterEstimate& p : fit.parameters) {
        if (p.effect != name) continue;
        params += fmt::format("{}{} = {:.4g}", params.empty() ? "" : ", ", p.name, p.value);
      }
      md += fmt::format("| {} | {} | {:.4g} | {} |\n", name, params, rms, apart);
    };
    if (!o.chosen.empty()) row(o.chosen.front()->name, s.chosen_fit, s.rms_after, "(chosen)");
    for (const EquivalentEffect& e : s.equivalent) {
      row(e.name, e.fit, e.rms_after,
          e.separating_channel.empty()
              ? std::string("-")
              : fmt::format("'{}', {:.2g} times its noise", e.separating_channel,
                            e.separation_over_noise));
    }
    md +=
        "\nBelow 1 times its noise, no channel of this record tells them apart: another "
        "channel, or a longer record, would.\n";
    md += "\n";
  }
  if (!o.before.signatures.empty()) {
    md += "## What stands out in the residual (declared model)\n\n";
    md += "| signature | channel | value (SI) | of the channel's range | points to |\n";
    md += "|---|---|---|---|---|\n";
    for (const Signature& sig : o.before.signatures) {
      std::string to;
      for (const std::string& f : sig.points_to) to += (to.empty() ? "" : ", ") + f;
      md += fmt::format("| {} | {} | {:.4g} | {:.1f} % | {} |\n", sig.kind, sig.channel, sig.value,
                        100 * sig.relative, to);
    }
    md += "\n";
  }
  md += "## Drop features: record, model before, model after\n\n";
  md += "| feature | channel | record | before | after |\n|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < o.before.features.size() && i < o.after.features.size(); ++i) {
    const FeatureComparison& b = o.before.features[i];
    md += fmt::format("| {} | {} | {:.5g} | {:.5g} | {:.5g} |\n", b.feature, b.channel, b.measured,
                      b.model, o.after.features[i].model);
  }
  md += "\n## Residual per channel (RMS, SI units)\n\n";
  md += "| channel | quantity | before | after | before trigger | impact | settled |\n";
  md += "|---|---|---|---|---|---|---|\n";
  for (std::size_t c = 0; c < o.before.channels.size(); ++c) {
    const ChannelResidual& b = o.before.channels[c];
    const ChannelResidual& a = o.after.channels[c];
    md += fmt::format(
        "| {} | {} | {:.4g} | {:.4g} | {:.3g} → {:.3g} | {:.3g} → {:.3g} | {:.3g} → "
        "{:.3g} |\n",
        b.column, b.description, b.rms, a.rms, b.rms_before, a.rms_before, b.rms_impact,
        a.rms_impact, b.rms_settled, a.rms_settled);
  }
  md +=
      "\n## Candidates\n\n| effect | suggested by the signatures | relative RMS with it | ΔBIC | "
      "accepted |\n|---|---|---|---|---|\n";
  // The registry's screened candidates that were not fitted are many: summarised below the
  // table, not a row each.
  std::vector<const CandidateScore*> screened_only;
  std::size_t screened_undecidable = 0;
  // A draw of the rotor's jitter that took the departure after an agreeing start came first,
  // and nothing was fitted (SelectEffects).
  const bool drawn_first = s.jitter.ran &&
                           (s.jitter.first_within > 0 || s.jitter.first_match > 0) &&
                           std::none_of(s.candidates.begin(), s.candidates.end(),
                                        [](const CandidateScore& c) { return c.tried; });
  std::size_t unscreened = 0;
  for (const CandidateScore& c : s.candidates) {
    if (drawn_first && c.screened) {
      ++unscreened;
      continue;
    }
    if (c.screened && !c.tried) {
      if (c.decidable && std::isfinite(c.screened_rms)) {
        screened_only.push_back(&c);
      } else {
        ++screened_undecidable;
      }
      continue;
    }
    if (!c.refused.empty()) {
      md +=
          fmt::format("| {} | | not fitted: the config refuses it ({}) | | |\n", c.name, c.refused);
      continue;
    }
    if (!c.decidable && std::isfinite(c.reach)) {
      md += fmt::format(
          "| {} | | not decidable from this record: even strong, it moves the prediction by {:.2g} "
          "only | | |\n",
          c.name, c.reach);
      continue;
    }
    if (!c.decidable) {
      md += fmt::format("| {} | | not decidable from these channels | | |\n", c.name);
      continue;
    }
    if (!c.tried) {
      md += fmt::format("| {} | {} | not fitted: {} | | |\n", c.name,
                        Suggested(o.before, c.family) ? "yes" : "",
                        drawn_first ? "a run of the declared model with the jitter drawn "
                                      "agreed first"
                                    : "the declared model agrees within the limit");
      continue;
    }
    md += fmt::format("| {} | {} | {:.4g} | {:.1f} | {} |\n", c.name,
                      Suggested(o.before, c.family) ? "yes" : "", c.rms_after, c.delta_bic,
                      c.accepted ? "yes" : "");
  }
  if (!screened_only.empty() || screened_undecidable > 0) {
    std::stable_sort(screened_only.begin(), screened_only.end(),
                     [](const CandidateScore* a, const CandidateScore* b) {
                       return a->screened_rms < b->screened_rms;
                     });
    md += fmt::format(
        "\n{} more candidates, \"the declared value is off\" for the config's other physical "
        "keys, were screened (three runs each) and not fitted: {} could not move the prediction "
        "beyond the agreement limit; the others' best predicted relative RMS:",
        screened_only.size() + screened_undecidable, screened_undecidable);
    for (std::size_t i = 0; i < screened_only.size() && i < 8; ++i) {
      md += fmt::format("{} {} ({:.3g})", i == 0 ? "" : ",", screened_only[i]->name,
                        screened_only[i]->screened_rms);
    }
    md += screened_only.size() > 8 ? ", ...\n" : "\n";
  }
  if (unscreened > 0) {
    md += fmt::format(
        "\n{} more candidates, \"the declared value is off\" for the config's other physical "
        "keys, were neither screened nor fitted.\n",
        unscreened);
  }
  md += "\n## Plots\n\n";
  for (const std::string& p : plots) md += fmt::format("![{}]({})\n\n", p, p);
  WriteTextFile(dir / "report.md", md);
}

}  // namespace ambdrop

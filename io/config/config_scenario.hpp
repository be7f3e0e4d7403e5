#pragma once
// The [scenario] table of a scenario file (configs/scenarios/). A scenario is a rig config like
// any other, usually `base = "../some_rig.toml"` plus the keys it changes (spin speed, unbalance
// phase, duration ...), with a [scenario] table that scripts what happens:
//
//   [scenario]
//   description = "power dip: the AMBs lose power for 100 ms and the controller re-levitates"
//   watchdog_timeout_s = 5e-3        # controller silence that trips the watchdog, s
//   silence_action = "hold"          # hold | zero | stop
//
//   [[scenario.event]]               # any number, any order
//   kind = "power_fail"              # power_fail | power_restore | trigger_glitch |
//                                    # sensor_dropout | stuck_current | controller_silence
//   time_s = 0.05                    # required, s
//   duration_s = 0.1                 # glitch, dropout, stuck current, silence (required), s
//   amb = "de"                       # power events, stuck current: one AMB (default: all)
//   axis = "y"                       # x | y | both (default both)
//   sensor = "de"                    # sensor_dropout: one sensor (default: all)
//   value_m = 0.0                    # sensor_dropout: what the sensor reads meanwhile, m
//
//   [scenario.expect]                # what must come out (all optional)
//   status = "ok"                    # ok | watchdog_stop | diverged
//   watchdog_silence_episodes = 1
//   power_events = 2
//   contact = true                   # some TDB touched
//   contact_at = ["de"]              # these TDBs touched
//   no_contact_at = ["nde"]
//   first_contact_after_s = 0.05     # nothing touched before this time, s
//   relevitated = true               # levitated again at the end
//
// The scenario's power events replace the rig's scheduled trigger: a scenario with any
// power_fail, power_restore or trigger_glitch event needs `[trigger] enabled = false`.
#include <optional>

#include "io/config/toml_reader.hpp"
#include "rt_core/model_params.hpp"
#include "rt_core/scenario_params.hpp"

namespace ambdrop {

/// Reads [scenario] strictly (unknown keys, bad kinds, unknown AMB/sensor/TDB names are
/// ConfigError with file:line and key). `params` gives the names.
ScenarioParams ReadScenario(const config_detail::TableReader& table, const ModelParams& params);

}  // namespace ambdrop

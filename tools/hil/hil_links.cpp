#include "tools/hil/hil_links.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "controller_if/controller/internal_controller_link.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "io/can/socketcan_bus.hpp"
#include "io/gpio/gpiod_lines.hpp"
#include "tools/hil/gpio_trigger_source.hpp"
#include "tools/hil/lcm_controller_link.hpp"

namespace ambdrop {
namespace {

bool StartsWith(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0;
}

const CanConfig& RequireCan(const LoadedConfig& config, const std::string& option) {
  if (!config.can) {
    throw ConfigError(fmt::format(
        "{}: {} needs a [can] table in the config (the frame map; see io/config/config_can.hpp and "
        "configs/jarroux2019_industrial_pid_can.toml)",
        config.source_path, option));
  }
  return *config.can;
}

GpioLineId ParseLineId(const std::string& text) {
  if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos) {
    return static_cast<unsigned>(std::stoul(text));
  }
  return text;
}

double ParseSeconds(const std::string& key, const std::string& value) {
  std::size_t used = 0;
  double seconds = -1.0;
  try {
    seconds = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || !std::isfinite(seconds) || seconds < 0.0) {
    throw std::invalid_argument(
        fmt::format("{}={}: expected a number of seconds >= 0", key, value));
  }
  return seconds;
}

void WriteCanCounters(JsonWriter& json, const char* key, const CanControllerLink& link,
                      const CanBus& bus) {
  const CanLinkCounters c = link.counters();
  const CanBusCounters b = bus.counters();
  const auto integer = [&json](const char* name, std::uint64_t value) {
    json.Key(name).Integer(static_cast<std::int64_t>(value));
  };
  json.Key(key).BeginObject();
  integer("frames_received", c.frames_received);
  integer("frames_decoded", c.decoded);
  integer("frames_unknown_id", c.unknown_id);
  integer("frames_malformed", c.malformed);
  integer("trigger_no_match", c.trigger_no_match);
  integer("receive_errors", c.receive_errors);
  integer("receive_overflows", b.receive_overflows);
  integer("frames_sent", c.frames_sent);
  integer("send_drops", c.send_drops);
  integer("send_errors", c.send_errors);
  integer("exchanges_sent", c.exchanges_sent);
  integer("samples_decimated", c.samples_decimated);
  integer("encode_saturations", c.encode_saturations);
  integer("power_events", c.power_events);
  integer("power_events_lost", c.power_events_lost);
  json.EndObject();
}

void WriteLcmCounters(JsonWriter& json, const LcmEndpointCounters& c) {
  const auto integer = [&json](const char* name, std::uint64_t value) {
    json.Key(name).Integer(static_cast<std::int64_t>(value));
  };
  json.Key("lcm").BeginObject();
  integer("currents_received", c.currents_received);
  integer("triggers_received", c.triggers_received);
  integer("malformed_decode", c.malformed_decode);
  integer("malformed_range", c.malformed_range);
  integer("malformed_non_finite", c.malformed_non_finite);
  integer("malformed_current_bound", c.malformed_current_bound);
  integer("currents_sequence_jumps", c.currents_sequence_jumps);
  integer("currents_ring_full", c.currents_ring_full);
  integer("triggers_ring_full", c.triggers_ring_full);
  integer("sensors_published", c.sensors_published);
  integer("sensors_ring_full", c.sensors_ring_full);
  integer("states_published", c.states_published);
  integer("states_ring_full", c.states_ring_full);
  integer("power_events_published", c.power_events_published);
  integer("power_events_ring_full", c.power_events_ring_full);
  integer("plant_requests", c.plant_requests);
  integer("plant_published", c.plant_published);
  integer("publish_rejected", c.publish_rejected);
  integer("publish_errors", c.publish_errors);
  integer("receive_errors", c.receive_errors);
  json.EndObject();
}

// A controller may ask for more than the amplifier gives (the model clips at current_limit_A);
// ten times that, or 10 kA on an AMB that declares no limit, is a broken sender.
constexpr double kCurrentBoundOverLimit = 10.0;
constexpr double kCurrentBoundWithoutLimit_A = 1e4;

}  // namespace

GpioTriggerSpec ParseGpioTrigger(const std::string& text) {
  const std::string usage =
      "expected gpio:CHIP:LINE[,fail=low|high][,debounce_s=S][,latch][,mirror=LINE]";
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    parts.push_back(text.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  const std::string& where = parts.front();
  const std::size_t colon = where.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == where.size()) {
    throw std::invalid_argument("--trigger gpio:" + text + ": " + usage);
  }
  GpioTriggerSpec spec;
  spec.input.chip = where.substr(0, colon);
  spec.input.line = ParseLineId(where.substr(colon + 1));
  spec.input.consumer = "ambdrop power-fail";
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const std::string& option = parts[i];
    const std::size_t equals = option.find('=');
    const std::string key = option.substr(0, equals);
    const std::string value = equals == std::string::npos ? "" : option.substr(equals + 1);
    if (key == "fail" && (value == "low" || value == "high")) {
      spec.trigger.fail_level = value == "low" ? PowerFailLevel::kLow : PowerFailLevel::kHigh;
    } else if (key == "debounce_s" && equals != std::string::npos) {
      spec.trigger.debounce_ns = std::llround(ParseSeconds(key, value) * 1e9);
    } else if (key == "latch" && equals == std::string::npos) {
      spec.trigger.honour_restore = false;
    } else if (key == "mirror" && !value.empty()) {
      spec.has_mirror = true;
      spec.mirror.chip = spec.input.chip;
      spec.mirror.line = ParseLineId(value);
      spec.mirror.consumer = "ambdrop drop state";
    } else {
      throw std::invalid_argument("--trigger gpio:" + text + ": option '" + option +
                                  "' not understood; " + usage);
    }
  }
  return spec;
}

void HilLinks::Stop() {
  if (lcm) lcm->Stop();
}

std::uint64_t HilLinks::RejectedControllerMessages() const {
  if (!lcm) return 0;
  const LcmEndpointCounters c = lcm->counters();
  return c.malformed_decode + c.malformed_range + c.malformed_non_finite +
         c.malformed_current_bound;
}

HilLinks::Answers HilLinks::ControllerAnswers(std::int64_t session_answers,
                                              std::int64_t session_samples) const {
  if (lcm) {
    const LcmEndpointCounters c = lcm->counters();
    return {static_cast<std::int64_t>(c.currents_received),
            static_cast<std::int64_t>(c.sensors_published + c.sensors_ring_full)};
  }
  if (can_link != nullptr) {
    return {session_answers, static_cast<std::int64_t>(can_link->counters().exchanges_sent)};
  }
  return {session_answers, session_samples};
}

void HilLinks::WriteSummary(JsonWriter& json) const {
  if (lcm) WriteLcmCounters(json, lcm->counters());
  if (can_link != nullptr) WriteCanCounters(json, "can", *can_link, *can_bus);
  if (can_trigger != nullptr) WriteCanCounters(json, "can_trigger", *can_trigger, *can_trigger_bus);
  if (gpio_trigger) {
    const GpioTriggerCounters& g = gpio_trigger->counters();
    json.Key("gpio_trigger").BeginObject();
    json.Key("edges").Integer(static_cast<std::int64_t>(g.edges));
    json.Key("glitches").Integer(static_cast<std::int64_t>(g.glitches));
    json.Key("failures").Integer(static_cast<std::int64_t>(g.failures));
    json.Key("restores").Integer(static_cast<std::int64_t>(g.restores));
    json.Key("restores_ignored").Integer(static_cast<std::int64_t>(g.restores_ignored));
    json.Key("repeated_edges").Integer(static_cast<std::int64_t>(g.repeated_edges));
    json.Key("events_overwritten").Integer(static_cast<std::int64_t>(g.events_overwritten));
    json.Key("read_errors").Integer(static_cast<std::int64_t>(g.read_errors));
    json.Key("mirror_errors").Integer(static_cast<std::int64_t>(g.mirror_errors));
    json.EndObject();
  }
}

HilLinks MakeHilLinks(const LoadedConfig& config, const Model& model, const std::string& controller,
                      const std::string& trigger) {
  HilLinks links;
  const double period_s = ControllerSubsteps(model) * model.params.simulation.step_s;
  LcmControllerLink* lcm_link = nullptr;

  // The controller.
  if (controller == "internal") {
    links.link = std::make_unique<InternalControllerLink>(model, period_s);
  } else if (controller == "lcm" || StartsWith(controller, "lcm:")) {
    LcmEndpointOptions lcm_options;
    if (controller.size() > 4) lcm_options.url = controller.substr(4);
    for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
      const double limit = model.params.ambs[a].current_limit_A;
      lcm_options.current_bound_A[a] =
          std::isfinite(limit) ? kCurrentBoundOverLimit * limit : kCurrentBoundWithoutLimit_A;
    }
    links.lcm = std::make_unique<LcmEndpoint>(lcm_options);
    links.lcm->Start();
    auto link = std::make_unique<LcmControllerLink>(links.lcm.get(),
                                                    static_cast<int>(model.params.sensors.size()));
    lcm_link = link.get();
    links.link = std::move(link);
  } else if (controller == "can" || StartsWith(controller, "can:")) {
    const CanConfig& can = RequireCan(config, "--controller " + controller);
    SocketCanOptions socket = can.SocketOptions();
    if (controller.size() > 4) socket.interface = controller.substr(4);
    // The loop's clock: receive times comparable with its deadlines.
    socket.timestamp = CanTimestampSource::kMonotonicAtRead;
    links.can_bus = std::make_unique<SocketCanBus>(socket);
    auto link = std::make_unique<CanControllerLink>(
        links.can_bus.get(), &can.frame_map,
        CanLinkOptions{.controller_period_s = period_s,
                       .exchange_rate_Hz = can.exchange_rate_Hz,
                       .tdb_count = static_cast<int>(model.params.tdbs.size())});
    links.can_link = link.get();
    links.link = std::move(link);
  } else {
    throw std::invalid_argument("--controller " + controller +
                                ": expected internal, lcm[:URL] or can[:IFACE]");
  }

  // The triggers.
  if (trigger.empty()) {
    if (model.params.trigger.enabled) {
      links.owned_triggers.push_back(std::make_unique<ScheduledTrigger>(
          model.params.trigger.time_s, ScheduledFailure(model), model.params.trigger.restore_time_s,
          ScheduledRestore(model)));
    }
  } else if (trigger == "lcm") {
    if (lcm_link == nullptr) throw std::invalid_argument("--trigger lcm needs --controller lcm");
    links.triggers.push_back(lcm_link);
  } else if (trigger == "can") {
    const CanConfig& can = RequireCan(config, "--trigger can");
    bool has_trigger = false;
    for (const CanSignalSpec& signal : can.frame_map.spec().signals) {
      has_trigger = has_trigger || signal.role == CanSignalRole::kPowerFail ||
                    signal.role == CanSignalRole::kPowerRestore;
    }
    if (!has_trigger) {
      throw ConfigError(fmt::format(
          "{}: --trigger can needs [can.trigger_in.power_fail] (or power_restore) in the config",
          config.source_path));
    }
    if (links.can_link != nullptr) {
      links.triggers.push_back(links.can_link);
    } else {
      // A receive-only socket that passes the trigger frames alone.
      SocketCanOptions socket = can.SocketOptions();
      socket.timestamp = CanTimestampSource::kMonotonicAtRead;
      socket.socket.filters.clear();
      for (const CanSignalSpec& signal : can.frame_map.spec().signals) {
        if (signal.role == CanSignalRole::kPowerFail ||
            signal.role == CanSignalRole::kPowerRestore) {
          socket.socket.filters.push_back(
              CanFilter::Exact(signal.layout.id, signal.layout.extended));
        }
      }
      links.can_trigger_bus = std::make_unique<SocketCanBus>(socket);
      auto link = std::make_unique<CanControllerLink>(links.can_trigger_bus.get(), &can.frame_map,
                                                      CanLinkOptions{});
      links.can_trigger = link.get();
      links.owned_triggers.push_back(std::move(link));
    }
  } else if (StartsWith(trigger, "gpio:")) {
    const GpioTriggerSpec spec = ParseGpioTrigger(trigger.substr(5));
    links.gpio_input = std::make_unique<GpiodInputLine>(spec.input);
    if (spec.has_mirror) {
      links.gpio_mirror = std::make_unique<GpiodOutputLine>(spec.mirror, false);
    }
    links.gpio_trigger =
        std::make_unique<GpioTrigger>(*links.gpio_input, links.gpio_mirror.get(), spec.trigger);
    if (links.gpio_trigger->Start() == GpioStatus::kError) {
      throw GpioError(fmt::format("--trigger {}: cannot read the input line's level (errno {})",
                                  trigger, links.gpio_input->last_errno()));
    }
    links.owned_triggers.push_back(std::make_unique<GpioTriggerSource>(links.gpio_trigger.get()));
  } else if (StartsWith(trigger, "at:")) {
    const double at = ParseSeconds("--trigger at", trigger.substr(3));
    links.owned_triggers.push_back(std::make_unique<ScheduledTrigger>(at, ScheduledFailure(model)));
  } else {
    throw std::invalid_argument("--trigger " + trigger +
                                ": expected at:SECONDS, lcm, can or gpio:CHIP:LINE[,OPTION...]");
  }
  for (const auto& owned : links.owned_triggers) links.triggers.push_back(owned.get());
  return links;
}

}  // namespace ambdrop

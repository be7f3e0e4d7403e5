#pragma once
// What `ambdrop hil` talks to, built from its --controller and --trigger options: the
// controller link, the trigger sources and the devices behind them (LCM endpoint, CAN sockets,
// GPIO lines). Setup code: it opens devices, allocates and throws; the links it returns are the
// real-time objects.
//
//   --controller internal        the reference PID in process
//   --controller lcm[:URL]       LCM (tools/hil/lcm_controller_link.hpp)
//   --controller can[:IFACE]     SocketCAN on IFACE (default: [can].interface), frames by the
//                                config's [can] frame map (tools/hil/can_controller_link.hpp)
//   --trigger at:SECONDS         power fails at a run time
//   --trigger lcm                AMBDROP_TRIGGER messages; needs --controller lcm
//   --trigger can                the [can] trigger_in frames: on the controller's bus with
//                                --controller can, else on a receive-only socket of its own on
//                                [can].interface (so the in-process controller can be dropped
//                                by `cansend vcan0 080#01`)
//   --trigger gpio:CHIP:LINE[,OPTION...]
//                                a power-fail input line (io/gpio/gpio_trigger.hpp). OPTIONs:
//                                fail=low|high (the level that means "power failed", default
//                                low: a PFAIL# line), debounce_s=S (default 0), latch (ignore
//                                power coming back), mirror=LINE (an output on the same chip
//                                driven to 1 while the rotor is dropped)
//   (none)                       the config's [trigger] schedule
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "controller_if/loop/controller_link.hpp"
#include "io/can/can_bus.hpp"
#include "io/config/config_loader.hpp"
#include "io/files/json_writer.hpp"
#include "io/gpio/gpio_line.hpp"
#include "io/gpio/gpio_trigger.hpp"
#include "io/lcm/lcm_transport.hpp"
#include "rt_core/model.hpp"
#include "tools/hil/can_controller_link.hpp"

namespace ambdrop {

/// Options of `--trigger gpio:CHIP:LINE[,OPTION...]`.
struct GpioTriggerSpec {
  GpioLineConfig input;
  GpioTriggerConfig trigger;
  bool has_mirror = false;
  GpioLineConfig mirror;
};

/// Parses the text after "gpio:"; throws std::invalid_argument saying what is wrong.
GpioTriggerSpec ParseGpioTrigger(const std::string& text);

/// The links of one `ambdrop hil` run and what they own. Not copyable; moves keep the pointers
/// valid (everything is on the heap).
struct HilLinks {
  std::unique_ptr<LcmEndpoint> lcm;
  std::unique_ptr<CanBus> can_bus;          ///< --controller can: the controller's socket
  std::unique_ptr<CanBus> can_trigger_bus;  ///< --trigger can beside another controller
  std::unique_ptr<GpioInputLine> gpio_input;
  std::unique_ptr<GpioOutputLine> gpio_mirror;
  std::unique_ptr<GpioTrigger> gpio_trigger;
  std::unique_ptr<ControllerLink> link;
  std::vector<std::unique_ptr<TriggerSource>> owned_triggers;
  std::vector<TriggerSource*> triggers;      ///< every trigger source, for HilSession
  CanControllerLink* can_link = nullptr;     ///< the CAN controller link, if any
  CanControllerLink* can_trigger = nullptr;  ///< the CAN trigger-only link, if any

  /// Stops the I/O threads (LCM) after the run.
  void Stop();
  /// Writes the LCM ("lcm"), CAN ("can", "can_trigger") and GPIO ("gpio_trigger") counters,
  /// when used.
  void WriteSummary(JsonWriter& json) const;
  /// Controller messages received and refused (LCM: not decodable, counts out of range, a
  /// current not finite or beyond its bound).
  std::uint64_t RejectedControllerMessages() const;
  /// Sensor samples that went out on the wire to an outside controller and the answers that
  /// came back, for the answered-fraction check. LCM: samples published and valid currents
  /// messages received (every one, also two within one period); CAN: exchanges sent (above the
  /// exchange rate only every n-th sample goes out) and `session_answers` (periods with new
  /// currents). Else `session_samples` and `session_answers`.
  struct Answers {
    std::int64_t answers = 0;
    std::int64_t samples = 0;
  };
  Answers ControllerAnswers(std::int64_t session_answers, std::int64_t session_samples) const;
};

/// Builds the links for `--controller` and `--trigger`. `config` (its [can] frame map) and
/// `model` must outlive the result. Throws std::invalid_argument for a bad option, ConfigError
/// when the config lacks what an option needs ([can]), CanBusError / GpioError when a device
/// cannot be opened.
HilLinks MakeHilLinks(const LoadedConfig& config, const Model& model, const std::string& controller,
                      const std::string& trigger);

}  // namespace ambdrop

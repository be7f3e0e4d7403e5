// ambdrop-controller: a stand-in external AMB controller. It runs the reference PID of a config
// (the same one `ambdrop sim` uses in process) on the sensor readings ambdrop publishes over LCM
// and answers with coil currents, so the whole HIL loop can be tried without a controller board:
//   ambdrop-controller CONFIG --lcm URL     and     ambdrop hil CONFIG --controller lcm:URL
//   ambdrop-controller CONFIG --can IFACE   and     ambdrop hil CONFIG --controller can:IFACE
// Over CAN it reads the sensor frames of the config's [can] frame map and answers each complete
// set with current frames; its PID runs at the exchange rate ([can].exchange_rate_Hz).
#include <fmt/format.h>
#include <lcm/lcm-cpp.hpp>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <optional>
#include <string>

#include "ambdrop_lcm/amb_currents_t.hpp"
#include "ambdrop_lcm/sensor_readings_t.hpp"
#include "controller_if/controller/pid_controller.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "io/can/can_controller_view.hpp"
#include "io/can/socketcan_bus.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"
#include "tools/hil/can_pid_responder.hpp"

namespace {

std::atomic<bool> g_stop{false};
extern "C" void OnSignal(int) {
  g_stop.store(true);
}

class Responder {
 public:
  Responder(lcm::LCM* lcm, const ambdrop::Model& model, double period_s, std::string out_channel)
      : lcm_(lcm), model_(model), controller_(model, period_s), out_(std::move(out_channel)) {}

  void OnSensors(const lcm::ReceiveBuffer*, const std::string&,
                 const ambdrop_lcm::sensor_readings_t* msg) {
    ambdrop::SensorReadings readings;
    const int n = std::min<int>(msg->sensor_count, ambdrop::kMaxSensors);
    for (int s = 0; s < n; ++s) readings.reading_m[s] = {msg->x_m[s], msg->y_m[s]};
    controller_.Update(readings, &input_);
    ambdrop_lcm::amb_currents_t out{};
    out.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                    std::chrono::system_clock::now().time_since_epoch())
                    .count();
    out.sequence = ++sequence_;
    out.amb_count = static_cast<int8_t>(model_.params.ambs.size());
    for (std::size_t a = 0; a < model_.params.ambs.size(); ++a) {
      out.current_x_A[a] = input_.amb[a].current_A[0];
      out.current_y_A[a] = input_.amb[a].current_A[1];
    }
    lcm_->publish(out_, &out);
    ++answered_;
    last_message_ = std::chrono::steady_clock::now();
  }
  std::int64_t answered() const { return answered_; }
  std::chrono::steady_clock::time_point last_message() const { return last_message_; }

 private:
  lcm::LCM* lcm_;
  const ambdrop::Model& model_;
  ambdrop::ReferenceController controller_;
  ambdrop::ControlInput input_;
  std::string out_;
  std::int64_t sequence_ = 0;
  std::int64_t answered_ = 0;
  std::chrono::steady_clock::time_point last_message_ = std::chrono::steady_clock::now();
};

/// One line once the controller answers: a script or an operator starting `ambdrop hil` after
/// it waits for this line, not for a guessed time (a loaded host once took longer than the
/// 0.5 s a test slept, and the rotor dropped before the first answer).
void AnnounceReady(const std::string& where) {
  fmt::print("ambdrop-controller: listening on {}\n", where);
  std::fflush(stdout);
}

/// The CAN variant of the loop: answers sensor frames until idle (or a signal).
int RunOverCan(const ambdrop::LoadedConfig& config, const ambdrop::Model& model,
               const std::string& interface, double idle_exit_s) {
  if (!config.can) {
    fmt::print(stderr,
               "error: {}: --can needs a [can] table in the config (the frame map; see "
               "configs/jarroux2019_industrial_pid_can.toml)\n",
               config.source_path);
    return 2;
  }
  const ambdrop::ControllerFrameView view(config.can->frame_map);
  ambdrop::SocketCanOptions options;
  options.interface = interface;
  options.socket.fd_frames = config.can->fd;
  options.socket.filters = view.InputFilters();
  std::optional<ambdrop::SocketCanBus> bus;
  try {
    bus.emplace(options);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
  ambdrop::CanPidResponder responder(&*bus, &view, model, 1.0 / config.can->exchange_rate_Hz);
  AnnounceReady("CAN " + interface);
  auto last_answer = std::chrono::steady_clock::now();
  while (!g_stop.load()) {
    if (responder.Service(std::chrono::milliseconds(100)) > 0) {
      last_answer = std::chrono::steady_clock::now();
    }
    const double idle =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - last_answer).count();
    if (responder.counters().sensor_sets > 0 && idle > idle_exit_s) break;
  }
  const ambdrop::CanResponderCounters& c = responder.counters();
  fmt::print(
      "ambdrop-controller: answered {} sensor sets over CAN ({} frames in, {} unknown, {} "
      "malformed; {} frames out, {} dropped)\n",
      c.sensor_sets, c.frames_received, responder.map_counters().unknown_id,
      responder.map_counters().malformed, c.frames_sent, c.send_drops);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ambdrop-controller: the reference PID as an external controller over LCM or CAN"};
  std::string config_path, url = "udpm://239.255.76.67:7667?ttl=0";
  std::vector<std::string> overrides;
  double idle_exit_s = 5.0;
  app.add_option("CONFIG", config_path, "TOML config (its [controller.pid] and AMBs)")->required();
  std::string can_interface;
  auto* lcm_option = app.add_option("--lcm", url, "LCM URL")->capture_default_str();
  app.add_option("--can", can_interface,
                 "SocketCAN interface (e.g. vcan0): talk CAN by the config's [can] frame map "
                 "instead of LCM")
      ->excludes(lcm_option);
  app.add_option("--set", overrides, "Override a config value (KEY=VALUE)")->take_all();
  app.add_option("--idle-exit-s", idle_exit_s,
                 "Exit after this long without sensor messages (once some arrived)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  std::optional<ambdrop::LoadedConfig> config;
  std::optional<ambdrop::Model> model;
  try {
    config.emplace(ambdrop::LoadConfig(config_path, overrides));
    model.emplace(ambdrop::BuildModel(config->params));
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  }
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  if (!can_interface.empty()) return RunOverCan(*config, *model, can_interface, idle_exit_s);
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    fmt::print(stderr, "error: cannot open LCM at {}\n", url);
    return 1;
  }
  const double period_s = ambdrop::ControllerSubsteps(*model) * model->params.simulation.step_s;
  Responder responder(&lcm, *model, period_s, "AMBDROP_CURRENTS");
  // subscribeFunction, not the member-function subscribe: GCC 12's -fsanitize=vptr crashes on
  // lcm-cpp's member-function thunk.
  lcm.subscribeFunction(
      "AMBDROP_SENSORS",
      +[](const lcm::ReceiveBuffer* rbuf, const std::string& channel,
          const ambdrop_lcm::sensor_readings_t* msg,
          Responder* r) { r->OnSensors(rbuf, channel, msg); },
      &responder);
  AnnounceReady("LCM " + url);
  while (!g_stop.load()) {
    lcm.handleTimeout(100);
    const double idle =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - responder.last_message())
            .count();
    if (responder.answered() > 0 && idle > idle_exit_s) break;
  }
  fmt::print("ambdrop-controller: answered {} sensor samples\n", responder.answered());
  return 0;
}
